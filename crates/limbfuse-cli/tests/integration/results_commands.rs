//! Every `limbfuse` command written in docs/RESULTS.md is accepted by the
//! command-line parser: the subcommand exists and every flag and value
//! parses (the command is run with `--help` appended, so clap validates the
//! words before it and then prints the help instead of doing the work).
//! Study examples and `cargo test` commands are checked by
//! `limbfuse-studies`'s `tests/integration/results_commands.rs`.

use std::path::Path;
use std::process::Command;

use limbfuse_studies::results_commands::{extract, CommandKind};

/// The problems of the `limbfuse` commands of `markdown`.
fn problems(markdown: &str) -> Vec<String> {
    let mut out = Vec::new();
    for c in extract(markdown) {
        let Ok(CommandKind::Limbfuse { args }) = c.kind() else {
            continue;
        };
        let o = Command::new(env!("CARGO_BIN_EXE_limbfuse"))
            .args(&args)
            .arg("--help")
            .output()
            .expect("run limbfuse");
        if !o.status.success() {
            out.push(format!(
                "line {}: `{}`: {}",
                c.line,
                c.text,
                String::from_utf8_lossy(&o.stderr).trim()
            ));
        }
    }
    out
}

#[test]
fn every_limbfuse_command_in_results_parses() {
    let md = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/RESULTS.md"),
    )
    .expect("docs/RESULTS.md");
    let n = extract(&md)
        .iter()
        .filter(|c| matches!(c.kind(), Ok(CommandKind::Limbfuse { .. })))
        .count();
    assert!(
        n >= 10,
        "only {n} limbfuse commands found in docs/RESULTS.md"
    );
    let p = problems(&md);
    assert!(p.is_empty(), "docs/RESULTS.md:\n{}", p.join("\n"));
}

#[test]
fn the_check_catches_broken_commands() {
    let md = "```sh\n\
        limbfuse no-such-command a.csv\n\
        limbfuse estimate --method mjls --no-such-flag a.csv -o b.csv\n\
        limbfuse resample a.csv --rate fifty -o b.csv\n\
        limbfuse resample a.csv --rate 50 -o b.csv\n\
        ```\n";
    assert_eq!(problems(md).len(), 3, "{:#?}", problems(md));
}
