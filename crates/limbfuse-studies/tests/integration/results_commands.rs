//! Every command written in docs/RESULTS.md is runnable (issue 13): each
//! study example it names exists and accepts its arguments (parsed by the
//! example's own parser, without running the study), each `cargo test`
//! command names an existing package and test target (a filter `MODULE::`
//! after `--` names a module of the target, `tests/NAME/MODULE.rs`), and no
//! study command is left abbreviated in the prose. `limbfuse` commands are
//! checked by `limbfuse-cli`'s `tests/integration/results_commands.rs`.
//! `scripts/results-commands.sh --run` runs them all (hours).

use std::path::{Path, PathBuf};

use limbfuse_studies::example_args::{check, EXAMPLES};
use limbfuse_studies::results_commands::{
    extract, inline_study_commands, unreproducible_markers, CommandKind,
};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn results_md() -> String {
    std::fs::read_to_string(workspace().join("docs/RESULTS.md")).expect("docs/RESULTS.md")
}

/// The problems of the commands of `markdown` that this crate can check.
fn problems(markdown: &str) -> Vec<String> {
    let root = workspace();
    let mut out = Vec::new();
    let commands = extract(markdown);
    for c in &commands {
        match c.kind() {
            Err(e) => out.push(e.to_string()),
            Ok(CommandKind::Limbfuse { .. }) => {}
            Ok(CommandKind::Example {
                package,
                example,
                args,
            }) => {
                if package != "limbfuse-studies" {
                    out.push(format!(
                        "line {}: study examples live in limbfuse-studies, not {package}",
                        c.line
                    ));
                } else if !root
                    .join(format!("crates/limbfuse-studies/examples/{example}.rs"))
                    .is_file()
                {
                    out.push(format!("line {}: no example file {example}.rs", c.line));
                } else if let Err(e) = check(&example, &args) {
                    out.push(format!("line {}: {e}", c.line));
                }
            }
            Ok(CommandKind::CargoTest {
                package,
                tests,
                args,
            }) => {
                let dir = root.join("crates").join(&package);
                if !dir.join("Cargo.toml").is_file() {
                    out.push(format!("line {}: no package {package}", c.line));
                }
                for t in &tests {
                    if !dir.join(format!("tests/{t}.rs")).is_file()
                        && !dir.join(format!("tests/{t}/main.rs")).is_file()
                    {
                        out.push(format!("line {}: {package} has no test {t}", c.line));
                    }
                }
                // A filter `MODULE::...` names a module of a test target
                // (tests/NAME/MODULE.rs, one per former test binary).
                for f in args.iter().filter(|a| !a.starts_with('-')) {
                    let Some((module, _)) = f.split_once("::") else {
                        continue;
                    };
                    let found = tests.iter().any(|t| {
                        dir.join(format!("tests/{t}/{module}.rs")).is_file()
                            || dir.join(format!("tests/{t}/{module}/mod.rs")).is_file()
                    });
                    if !found {
                        out.push(format!(
                            "line {}: no test module {module} in {package} {tests:?}",
                            c.line
                        ));
                    }
                }
            }
        }
    }
    for (line, span) in inline_study_commands(markdown) {
        if !commands.iter().any(|c| c.text == span) {
            out.push(format!(
                "line {line}: `{span}` is not written out as a command of a ```sh block"
            ));
        }
    }
    out
}

#[test]
fn every_results_command_is_runnable() {
    let md = results_md();
    assert!(
        extract(&md).len() > 20,
        "docs/RESULTS.md lost its ```sh blocks"
    );
    let p = problems(&md);
    assert!(p.is_empty(), "docs/RESULTS.md:\n{}", p.join("\n"));
}

#[test]
fn the_check_catches_broken_commands() {
    let md = "```sh\n\
        cargo run --release -p limbfuse-studies --example no_such_study\n\
        cargo run --release -p limbfuse-studies --example knee_study -- seeds 30 0 rate-bais\n\
        cargo run --release -p limbfuse-studies --example imm_bslip_study -- --truth 0.65\n\
        cargo run --release -p limbfuse-eval --example knee_study -- seeds\n\
        cargo test -p limbfuse-studies --test no_such_test\n\
        cargo test -p limbfuse-studies --test integration -- no_such_module::\n\
        cargo test -p limbfuse-studies --test integration -- results_commands::\n\
        IMM_WEIGHTS=recursive cargo run --release -p limbfuse-studies --example imm_bslip_study\n\
        ```\n\
        and `cargo run --release -p limbfuse-studies --example segment_study -- 30`\n";
    let p = problems(md);
    assert_eq!(p.len(), 8, "{p:#?}");
}

/// Issue 13's last "done when": no figure of docs/RESULTS.md is left without
/// a committed command (a figure measured by an undone edit or a script
/// outside the repository says so with one of the markers).
#[test]
fn issue_13_no_figure_without_a_committed_command() {
    let found: Vec<String> = unreproducible_markers(&results_md())
        .into_iter()
        .map(|(line, m)| format!("docs/RESULTS.md:{line}: \"{m}\""))
        .collect();
    assert!(
        found.is_empty(),
        "figures without a committed command (make them reproducible, or name the \
         commit whose docs/RESULTS.md holds them with their command):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_marker_check_catches_unreproducible_figures() {
    let md = "a 1.2 deg figure (measured with a Temporary edit, reverted)\n\
        and 3.4 deg by an ad-hoc script: not reproducible by a committed command\n\
        a 5.6 deg figure with its command; 7.8 deg, Not\n   reproducible (split)\n";
    let lines: Vec<usize> = unreproducible_markers(md).iter().map(|m| m.0).collect();
    assert_eq!(lines, vec![1, 1, 2, 2, 3]);
}

#[test]
fn every_example_has_an_argument_parser() {
    let mut files: Vec<String> =
        std::fs::read_dir(workspace().join("crates/limbfuse-studies/examples"))
            .expect("examples dir")
            .filter_map(|e| {
                let p = e.ok()?.path();
                (p.extension()? == "rs").then(|| p.file_stem()?.to_str().map(str::to_string))?
            })
            .collect();
    files.sort();
    assert_eq!(files, EXAMPLES.to_vec());
    for e in EXAMPLES {
        // Bad arguments are refused by every example's parser.
        assert!(check(e, &["--no-such-flag".into()]).is_err(), "{e}");
    }
}
