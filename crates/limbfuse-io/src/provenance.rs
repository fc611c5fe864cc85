//! Provenance lines of the files limbfuse writes besides trials and
//! estimates (the `montecarlo` CSV and SVG, the `calibrate` file): which
//! limbfuse made the file, with which command and settings, from which
//! input (docs/OUTPUTS.md section 3). Each is a `# key: value` comment line,
//! the form of an estimate file's `# command:` and `# trial_hash:`, so every
//! reader that skips `#` lines (the calibration reader, pandas with
//! `comment="#"`) reads the file as before.

/// The version of limbfuse that writes a file (`# limbfuse_version:`).
pub const LIMBFUSE_VERSION: &str = env!("CARGO_PKG_VERSION");

/// Header key of the writing limbfuse's version.
pub const VERSION_KEY: &str = "limbfuse_version";

/// Header key of the command that wrote a file.
pub const COMMAND_KEY: &str = "command";

/// `value` on one line: line breaks and other control characters (a file
/// name may hold them) become spaces, so that a value cannot end its
/// comment line and start a line the file's reader would parse.
pub fn one_line(value: &str) -> String {
    value
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

/// The `key: value` lines, each on one line ([`one_line`]), without the
/// comment marker (the caller writes `# ` or puts them in an SVG).
pub fn lines(pairs: &[(&str, String)]) -> Vec<String> {
    pairs
        .iter()
        .map(|(k, v)| format!("{}: {}", one_line(k), one_line(v)))
        .collect()
}

/// The `# key: value` comment lines of `pairs`, each ended by `\n`.
pub fn comment_lines(pairs: &[(&str, String)]) -> String {
    lines(pairs).iter().map(|l| format!("# {l}\n")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_value_cannot_break_its_comment_line() {
        let text = comment_lines(&[("command", "limbfuse calibrate 'a\nb.csv'\r".into())]);
        assert_eq!(text, "# command: limbfuse calibrate 'a b.csv' \n");
        assert_eq!(text.lines().count(), 1);
    }
}
