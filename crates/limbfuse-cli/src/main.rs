//! `limbfuse`: estimate lower-limb angles from wearable IMUs and exoskeleton
//! encoders. A thin layer over the limbfuse crates: flags are parsed and
//! validated once here, then the library does the work.
#![deny(missing_docs)]

mod bounds;
mod cli;
mod cli_calibration;
mod cli_simulate;
mod commands;
mod exit;
mod methods;
mod progress;
mod stdio;

use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches};

fn main() -> ExitCode {
    exit::install_panic_hook();
    let cli = match parse_args() {
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

/// Parses the command line. Every command accepts negative numbers as
/// values, so that `--duration -5` reaches the range check of its flag
/// ("expected a positive number") instead of clap's "unexpected argument
/// '-5'" (issue 17 item 6).
fn parse_args() -> Result<cli::Cli, clap::Error> {
    fn negative_numbers_are_values(cmd: clap::Command) -> clap::Command {
        cmd.allow_negative_numbers(true)
            .mut_subcommands(negative_numbers_are_values)
    }
    let mut cmd = negative_numbers_are_values(cli::Cli::command());
    let matches = cmd.try_get_matches_from_mut(std::env::args_os())?;
    cli::Cli::from_arg_matches(&matches).map_err(|e| e.format(&mut cmd))
}
