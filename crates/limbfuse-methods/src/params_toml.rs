//! What every parameter file (`--params FILE.toml`) shares: TOML read into a
//! method's typed file struct (`deny_unknown_fields`), errors that name the
//! file, line, column and key.

use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;

/// Why a parameter file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum ParamsFileError {
    /// The file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// File path.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// Not valid TOML, an unknown key or a value of the wrong type.
    #[error("{}:{line}:{column}: {}", path.display(), crate::clip_echoes(message))]
    Syntax {
        /// File path.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong (names the key).
        message: String,
    },
    /// A key that does not apply or a value out of range.
    #[error("{}: {}", path.display(), crate::clip_echoes(message))]
    Invalid {
        /// File path.
        path: PathBuf,
        /// What is wrong (names the key and the accepted range).
        message: String,
    },
}

/// 1-based line and column of byte `offset` in `text`.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before
        .rfind('\n')
        .map_or(before.len(), |k| before.len() - k - 1)
        + 1;
    (line, col)
}

/// Reads a parameter file's text.
pub fn read(path: &Path) -> Result<String, ParamsFileError> {
    limbfuse_io::bounded_text::read_text_at_most(
        path,
        limbfuse_io::bounded_text::MAX_SETTINGS_FILE_BYTES,
        "a parameter file (TOML, a few KB)",
    )
    .map_err(|source| ParamsFileError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Parses `text` into a method's typed file struct; `path` names it in
/// errors, which carry the line and column of the offending key or value.
pub fn from_str<T: DeserializeOwned>(text: &str, path: &Path) -> Result<T, ParamsFileError> {
    toml::from_str(text).map_err(|e| {
        let (line, column) = e.span().map_or((1, 1), |s| line_col(text, s.start));
        ParamsFileError::Syntax {
            path: path.to_path_buf(),
            line,
            column,
            message: e.message().trim().to_string(),
        }
    })
}

/// A file's top-level `method = "NAME"` line against the method it is
/// read for (`expected`), checked before the file is parsed for that
/// method: an audit found an `sdre` file given to `mjls` reported as
/// "unknown field `measurement`", which hides the mix-up. Text that is not
/// TOML passes here (the typed parse names the line and column).
pub fn check_method_line(text: &str, path: &Path, expected: &str) -> Result<(), ParamsFileError> {
    let Ok(table) = text.parse::<toml::Table>() else {
        return Ok(());
    };
    // (an audit: a calibration file given as --params was "unknown field
    // `format`")
    if let Some(format) = table.get("format").and_then(toml::Value::as_str) {
        if format.starts_with("limbfuse-imu-calibration") {
            return Err(ParamsFileError::Invalid {
                path: path.to_path_buf(),
                message: format!(
                    "a sensor calibration file (`format = \"{format}\"`, limbfuse calibrate), not \
                     a parameter file: give it with --calibration"
                ),
            });
        }
    }
    match table.get("method").and_then(toml::Value::as_str) {
        Some(found) => crate::name::check_file_method(found, expected, path),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn another_methods_file_is_named_before_its_keys() {
        let p = Path::new("p.toml");
        let e = check_method_line("method = \"sdre\"\n[measurement]\n", p, "mjls").unwrap_err();
        assert!(e
            .to_string()
            .contains("`method` = \"sdre\" but the file is read for method `mjls`"));
        assert!(check_method_line("method = \"mjls\"\n", p, "mjls").is_ok());
        assert!(check_method_line("gravity = 9.81\n", p, "mjls").is_ok());
        assert!(check_method_line("not toml [", p, "mjls").is_ok());
    }

    #[test]
    fn line_and_column_are_one_based() {
        assert_eq!(line_col("ab\ncd", 0), (1, 1));
        assert_eq!(line_col("ab\ncd", 4), (2, 2));
    }

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Two {
        a: f64,
    }

    #[test]
    fn unknown_keys_name_line_and_column() {
        let e = from_str::<Two>("a = 1.0\nbee = 2\n", Path::new("f.toml")).unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with("f.toml:2:1:"), "{msg}");
        assert!(msg.contains("bee"), "{msg}");
    }
}
