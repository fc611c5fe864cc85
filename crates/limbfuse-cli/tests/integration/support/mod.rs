//! What every CLI integration test needs: the `limbfuse` binary built for
//! this test run, run with arguments in a directory.

use std::path::Path;
use std::process::{Command, Output};

/// Runs the `limbfuse` binary of this build with `args` in `dir` and
/// returns its exit status and output (panics only when the binary cannot
/// be started at all, which is a broken build, not a test outcome).
pub fn limbfuse(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_limbfuse"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}
