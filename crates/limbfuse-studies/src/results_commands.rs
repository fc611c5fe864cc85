//! The commands written in `docs/RESULTS.md`: every non-blank line of a
//! ```` ```sh ```` block that is not a `#` comment is one command, run from
//! the repository root (or a directory beside it, see
//! `scripts/results-commands.sh`). [`extract`] lists them, [`ResultsCommand::kind`]
//! says what each runs; `tests/integration/results_commands.rs` (here, for the study
//! examples and `cargo test` commands) and `limbfuse-cli`'s
//! `tests/integration/results_commands.rs` (for `limbfuse` commands) check that each is
//! runnable.

/// One command of a ```` ```sh ```` block.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ResultsCommand {
    /// 1-based line in the Markdown file.
    pub line: usize,
    /// The command as written.
    pub text: String,
}

/// What a command runs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CommandKind {
    /// `cargo run [--release] -p PACKAGE --example NAME [-- ARGS]`.
    Example {
        /// The package.
        package: String,
        /// The example.
        example: String,
        /// The example's arguments.
        args: Vec<String>,
    },
    /// `cargo test -p PACKAGE (--test NAME)* [-- ARGS]`.
    CargoTest {
        /// The package.
        package: String,
        /// The integration test targets.
        tests: Vec<String>,
        /// The test harness's arguments (after `--`): name filters such as
        /// `MODULE::` (a module of a test target) and options.
        args: Vec<String>,
    },
    /// `limbfuse ARGS` (the installed command-line tool).
    Limbfuse {
        /// Its arguments.
        args: Vec<String>,
    },
}

/// Why a command cannot be classified.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CommandError {
    /// A shell feature the checks do not follow (pipes, redirection,
    /// quoting, environment assignments, `[optional]` parts, `...`).
    #[error("line {line}: `{text}`: write one plain command (no `{what}`)")]
    NotPlain {
        /// Line in the file.
        line: usize,
        /// The command.
        text: String,
        /// The offending part.
        what: String,
    },
    /// Not `cargo run`, `cargo test` or `limbfuse`, or a `cargo` option
    /// the checks do not know.
    #[error("line {line}: `{text}`: {why}")]
    Unsupported {
        /// Line in the file.
        line: usize,
        /// The command.
        text: String,
        /// What is wrong.
        why: String,
    },
}

/// Every command of the ```` ```sh ```` blocks of `markdown`, in order.
pub fn extract(markdown: &str) -> Vec<ResultsCommand> {
    let mut out = Vec::new();
    let mut in_sh = false;
    for (i, line) in markdown.lines().enumerate() {
        let t = line.trim();
        if t.starts_with("```") {
            in_sh = !in_sh && t == "```sh";
            continue;
        }
        if in_sh && !t.is_empty() && !t.starts_with('#') {
            out.push(ResultsCommand {
                line: i + 1,
                text: t.to_string(),
            });
        }
    }
    out
}

/// Words that say a figure was measured by something no committed command
/// runs (an edit made and undone, a script outside the repository, code no
/// commit holds). `docs/RESULTS.md` must not contain them (issue 13: every
/// figure is reproduced by a committed command written next to it; a
/// "before" figure of code that has since changed names the commit whose
/// docs/RESULTS.md holds it with its command).
pub const UNREPRODUCIBLE_MARKERS: [&str; 8] = [
    "not reproducible",
    "ad-hoc",
    "ad hoc",
    "uncommitted",
    "temporary",
    "scoring script",
    "reverted",
    "by editing",
];

/// Where `markdown` contains one of [`UNREPRODUCIBLE_MARKERS`]
/// (case-insensitive, also across a line break): the 1-based line where the
/// marker starts, with the marker.
pub fn unreproducible_markers(markdown: &str) -> Vec<(usize, &'static str)> {
    // The words joined by single spaces, with the line each starts on.
    let mut text = String::new();
    let mut starts: Vec<(usize, usize)> = Vec::new();
    for (i, line) in markdown.lines().enumerate() {
        for w in line.split_whitespace() {
            if !text.is_empty() {
                text.push(' ');
            }
            starts.push((text.len(), i + 1));
            text.push_str(&w.to_lowercase());
        }
    }
    let line_at = |offset: usize| {
        let k = starts.partition_point(|&(o, _)| o <= offset);
        starts[k.saturating_sub(1)].1
    };
    let mut out = Vec::new();
    for m in UNREPRODUCIBLE_MARKERS {
        out.extend(text.match_indices(m).map(|(o, _)| (line_at(o), m)));
    }
    out.sort();
    out
}

/// Inline code spans (single backticks) of `markdown` that look like a
/// study command (`cargo run`, `cargo test -p`, `--example`) or an abbreviated
/// one (starting with `...` or `-- `), with their line: such a span must be
/// written out as a ```` ```sh ```` block command too.
pub fn inline_study_commands(markdown: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut in_block = false;
    let mut span: Option<(usize, String)> = None;
    for (i, line) in markdown.lines().enumerate() {
        if line.trim().starts_with("```") {
            in_block = !in_block;
            continue;
        }
        if in_block {
            continue;
        }
        for c in line.chars() {
            match (&mut span, c) {
                (None, '`') => span = Some((i + 1, String::new())),
                (Some(_), '`') => {
                    let (l, s) = span.take().unwrap_or_default();
                    let s = s.split_whitespace().collect::<Vec<_>>().join(" ");
                    if s.contains("cargo run")
                        || s.contains("cargo test -p")
                        || s.contains("--example")
                        || s.starts_with("...")
                        || s.starts_with("-- ")
                    {
                        out.push((l, s));
                    }
                }
                (Some((_, s)), c) => s.push(c),
                (None, _) => {}
            }
        }
        if let Some((_, s)) = &mut span {
            s.push(' ');
        }
    }
    out
}

impl ResultsCommand {
    /// The command's words (split on whitespace).
    pub fn words(&self) -> Vec<String> {
        self.text.split_whitespace().map(str::to_string).collect()
    }

    /// What the command runs.
    pub fn kind(&self) -> Result<CommandKind, CommandError> {
        let not_plain = |what: &str| CommandError::NotPlain {
            line: self.line,
            text: self.text.clone(),
            what: what.into(),
        };
        for bad in ["|", ">", "<", ";", "&", "'", "\"", "$", "[", "...", "\\"] {
            if self.text.contains(bad) {
                return Err(not_plain(bad));
            }
        }
        let words = self.words();
        if words.first().is_some_and(|w| w.contains('=')) {
            return Err(not_plain("VAR=value"));
        }
        let unsupported = |why: String| CommandError::Unsupported {
            line: self.line,
            text: self.text.clone(),
            why,
        };
        match words.iter().map(String::as_str).collect::<Vec<_>>()[..] {
            ["limbfuse", ..] => Ok(CommandKind::Limbfuse {
                args: words[1..].to_vec(),
            }),
            ["cargo", "run", ..] => {
                let (opts, args) = split_at_dashes(&words[2..]);
                let (package, mut named) = cargo_options(opts, &["--example"])
                    .map_err(|w| unsupported(format!("unknown cargo run option `{w}`")))?;
                let example = named
                    .pop()
                    .ok_or_else(|| unsupported("no --example".into()))?;
                Ok(CommandKind::Example {
                    package: package.ok_or_else(|| unsupported("no -p PACKAGE".into()))?,
                    example,
                    args,
                })
            }
            ["cargo", "test", ..] => {
                let (opts, args) = split_at_dashes(&words[2..]);
                let (package, tests) = cargo_options(opts, &["--test"])
                    .map_err(|w| unsupported(format!("unknown cargo test option `{w}`")))?;
                Ok(CommandKind::CargoTest {
                    package: package.ok_or_else(|| unsupported("no -p PACKAGE".into()))?,
                    tests,
                    args,
                })
            }
            _ => Err(unsupported(
                "not `cargo run`, `cargo test` or `limbfuse`".into(),
            )),
        }
    }
}

/// The words before and after the first `--`.
fn split_at_dashes(words: &[String]) -> (&[String], Vec<String>) {
    match words.iter().position(|w| w == "--") {
        Some(i) => (&words[..i], words[i + 1..].to_vec()),
        None => (words, Vec::new()),
    }
}

/// `-p PACKAGE` and the values of the options named in `valued` (each
/// followed by a value); `--release` and `-q` are allowed; any other word
/// is returned as the error.
fn cargo_options(
    opts: &[String],
    valued: &[&str],
) -> Result<(Option<String>, Vec<String>), String> {
    let mut package = None;
    let mut values = Vec::new();
    let mut it = opts.iter();
    while let Some(w) = it.next() {
        match w.as_str() {
            "--release" | "-q" => {}
            "-p" => package = it.next().cloned(),
            w if valued.contains(&w) => values.extend(it.next().cloned()),
            w => return Err(w.to_string()),
        }
    }
    Ok((package, values))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extracts_sh_blocks_and_classifies() {
        let md = "text `cargo run -p x --example y`\n```sh\n# comment\ncargo run --release -p limbfuse-studies --example knee_study -- seeds 30\n\nlimbfuse resample a.csv --rate 50 -o b.csv\n```\n```text\ncargo run not a command\n```\n";
        let c = extract(md);
        assert_eq!(c.len(), 2);
        assert_eq!(c[0].line, 4);
        assert_eq!(
            c[0].kind(),
            Ok(CommandKind::Example {
                package: "limbfuse-studies".into(),
                example: "knee_study".into(),
                args: vec!["seeds".into(), "30".into()],
            })
        );
        assert!(matches!(c[1].kind(), Ok(CommandKind::Limbfuse { .. })));
        assert_eq!(
            inline_study_commands(md),
            vec![(1, "cargo run -p x --example y".to_string())]
        );
        let bad = ResultsCommand {
            line: 1,
            text: "IMM_WEIGHTS=recursive cargo run -p a --example b".into(),
        };
        assert!(matches!(bad.kind(), Err(CommandError::NotPlain { .. })));
        let bad = ResultsCommand {
            line: 1,
            text: "cargo run -p a --example b 30".into(),
        };
        assert!(matches!(bad.kind(), Err(CommandError::Unsupported { .. })));
    }
}
