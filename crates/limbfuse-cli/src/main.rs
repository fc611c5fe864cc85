//! `limbfuse`: estimate lower-limb angles from wearable IMUs and exoskeleton
//! encoders. A thin layer over the limbfuse crates: flags are parsed and
//! validated once here, then the library does the work.
#![deny(missing_docs)]

mod bounds;
mod cli;
mod cli_calibration;
mod commands;
mod exit;
mod methods;
mod progress;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    exit::install_panic_hook();
    let cli = match cli::Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let user_asked = matches!(
                e.kind(),
                clap::error::ErrorKind::DisplayHelp | clap::error::ErrorKind::DisplayVersion
            );
            let _ = e.print();
            return if user_asked {
                ExitCode::SUCCESS
            } else {
                ExitCode::from(exit::USER_ERROR)
            };
        }
    };
    match commands::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => exit::report(&e),
    }
}
