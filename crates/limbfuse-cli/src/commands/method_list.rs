//! `limbfuse methods` (every method, its inputs and settings) and
//! `limbfuse params --method NAME` (its default parameter file).

use anyhow::Result;
use limbfuse_methods::{default_params_file, MethodName};

use crate::cli::ParamsArgs;

/// Prints every method.
pub fn list() -> Result<()> {
    for m in MethodName::ALL {
        let i = m.info();
        println!("{}\n    {}", i.name, i.summary);
        println!("    reads:    {}", i.inputs);
        println!("    settings: {}", i.settings);
    }
    println!(
        "\n`limbfuse params --method NAME` writes a method's default parameter file (--params)."
    );
    Ok(())
}

/// Writes the default parameter file of `--method`.
pub fn params(a: &ParamsArgs) -> Result<()> {
    let method = MethodName::parse(&a.method)?;
    let text = default_params_file(method);
    match &a.output {
        Some(p) if !crate::stdio::is_stdio(p) => {
            super::write_file(p, &text)?;
            eprintln!("{method} defaults -> {}", p.display());
        }
        _ => print!("{text}"),
    }
    Ok(())
}
