//! A gait library file without one of its gaits (the held-out library of
//! docs/RESULTS.md's single `limbfuse` runs of paper 003 sec IV-A; `limbfuse
//! gait-library build` takes a START:END:STEP range only).
//! `cargo run --release -p limbfuse-studies --example gait_library_without -- LIBRARY SPEED -o OUTPUT`

use std::path::Path;

use clap::Parser;
use limbfuse_io::gait_library::GaitLibraryFile;
use limbfuse_studies::example_args::GaitLibraryWithoutArgs;

fn main() {
    let args = GaitLibraryWithoutArgs::parse();
    let path = Path::new(&args.library);
    let mut lib = GaitLibraryFile::read(path).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(1)
    });
    let before = lib.gaits.len();
    lib.gaits.retain(|g| (g.speed - args.speed).abs() > 1e-6);
    if lib.gaits.len() + 1 != before {
        eprintln!(
            "{}: no gait at {} m/s (speeds: {:?})",
            path.display(),
            args.speed,
            lib.gaits.iter().map(|g| g.speed).collect::<Vec<_>>()
        );
        std::process::exit(1);
    }
    let out = Path::new(&args.output);
    lib.write(out).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(1)
    });
    eprintln!(
        "wrote {} ({} gaits, {} m/s left out)",
        out.display(),
        lib.gaits.len(),
        args.speed
    );
}
