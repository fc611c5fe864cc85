//! Outputs that would replace an input, or each other.
//!
//! An audit found `estimate c.csv -o c.csv` replaced the recording with
//! its estimate (exit 0); a later one found the same for `tune`,
//! `calibrate`, `report` and `simulate bslip --library`, and two outputs of
//! one command given the same name (`montecarlo -o m.csv --svg m.csv`,
//! `simulate knee-fes --calibration`) reported both written while one
//! replaced the other. Each is refused before anything runs, exit 1.

use std::path::{Path, PathBuf};

use anyhow::Result;
use limbfuse_io::file_identity::same_file;

/// An output that names the input file would replace the recording with
/// what was made from it: refused, exit 1.
pub fn refuse_input_as_output(input: &Path, output: &Path) -> Result<()> {
    refuse_overwrites(&[("", Some(input))], &[("-o", Some(output))])
}

/// Refuses any output (flag, path) that names one of the inputs (flag,
/// path; flag `""` for the positional input), and any two outputs that name
/// one file. Absent optional paths are `None`.
pub fn refuse_overwrites(
    inputs: &[(&str, Option<&Path>)],
    outputs: &[(&str, Option<&Path>)],
) -> Result<()> {
    let present = |v: &[(&str, Option<&Path>)]| -> Vec<(String, PathBuf)> {
        v.iter()
            .filter_map(|(f, p)| Some((f.to_string(), (*p)?.to_path_buf())))
            .collect()
    };
    let (inputs, outputs) = (present(inputs), present(outputs));
    for (flag, out) in &outputs {
        for (in_flag, input) in &inputs {
            if same_file(input, out) {
                let named = if in_flag.is_empty() {
                    String::new()
                } else {
                    format!(" ({in_flag})")
                };
                anyhow::bail!(
                    "{flag} {}: that is the input file {}{named}; writing would replace it: give \
                     the output another name",
                    out.display(),
                    input.display()
                );
            }
        }
    }
    for (k, (flag, out)) in outputs.iter().enumerate() {
        for (other_flag, other) in &outputs[k + 1..] {
            if same_file(out, other) {
                anyhow::bail!(
                    "{other_flag} {}: the same file as {flag} {}; one would replace the other: \
                     give each output its own name",
                    other.display(),
                    out.display()
                );
            }
        }
    }
    Ok(())
}

/// An output whose folder does not exist, or that is an existing folder,
/// refused before a long run (an audit: `tune ... -o /nonexistent/x.toml`
/// failed after its whole search, 8 s there; `gait-library build -o DIR`
/// after its 3 s search, with "Is a directory (os error 21)").
pub fn refuse_missing_folder(flag: &str, output: &Path) -> Result<()> {
    let folder = match output.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let named = match flag {
        "" => output.display().to_string(),
        f => format!("{f} {}", output.display()),
    };
    if !folder.is_dir() {
        anyhow::bail!("{named}: the folder {} does not exist", folder.display());
    }
    if output.is_dir() {
        anyhow::bail!(
            "{named}: that is a folder; the output is a file: give a file name (e.g. {})",
            output.join("out").display()
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_output_naming_an_input_or_another_output_is_refused() {
        let d = tempfile::tempdir().unwrap();
        let trial = d.path().join("t.csv");
        std::fs::write(&trial, "t\n0\n").unwrap();
        let dotted = d.path().join(".").join("t.csv");
        let fresh = d.path().join("new.csv");
        let fresh2 = d.path().join(".").join("new.csv");
        let other = d.path().join("other.svg");
        let e = refuse_overwrites(&[("", Some(&trial))], &[("-o", Some(&dotted))]).unwrap_err();
        assert!(e.to_string().contains("that is the input file"), "{e}");
        let e =
            refuse_overwrites(&[("--params", Some(&trial))], &[("-o", Some(&trial))]).unwrap_err();
        assert!(e.to_string().contains("(--params)"), "{e}");
        // Neither output exists yet: still one file.
        let e =
            refuse_overwrites(&[], &[("-o", Some(&fresh)), ("--svg", Some(&fresh2))]).unwrap_err();
        assert!(e.to_string().starts_with("--svg"), "{e}");
        refuse_overwrites(
            &[("", Some(&trial)), ("--params", None)],
            &[("-o", Some(&fresh)), ("--svg", Some(&other)), ("--x", None)],
        )
        .unwrap();
        // Standard input and output are never a file here.
        refuse_overwrites(
            &[("", Some(Path::new("-")))],
            &[("-o", Some(Path::new("-")))],
        )
        .unwrap();
    }
}
