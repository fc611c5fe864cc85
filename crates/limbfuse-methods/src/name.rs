//! Parsing method names. [`MethodName::parse`] (and [`check_file_method`]
//! for a parameter file's `method` line) are the one place in limbfuse where
//! a method name is compared with a string; every other decision is a
//! `match` on [`MethodName`], which the registry ([`crate::registry`])
//! declares.

use core::fmt;
use std::path::Path;

pub use crate::registry::MethodName;
use crate::segment_params::ParamsFileError;

impl MethodName {
    /// The `--method` name.
    pub const fn name(self) -> &'static str {
        self.info().name
    }

    /// Parses a `--method` name (or a file's `method` / `# method:` value).
    pub fn parse(text: &str) -> Result<MethodName, UnknownMethod> {
        let text = text.trim();
        Self::ALL
            .into_iter()
            .find(|m| m.name() == text)
            .ok_or_else(|| UnknownMethod(text.to_string()))
    }

    /// Whether the method's diagnostics include coupled relative rows
    /// (`upd_hip`, `upd_knee`, `upd_ankle` of the global filter's relative
    /// accelerometer rows, 001 eq 21), counted by the AGR of `evaluate`.
    pub const fn has_relative_rows(self) -> bool {
        self.info().relative_rows
    }

    /// The methods `limbfuse demo` runs on its walking trial.
    pub fn walking_demo() -> impl Iterator<Item = MethodName> {
        Self::ALL.into_iter().filter(|m| m.info().in_walking_demo)
    }

    /// Every name, comma-separated (for messages).
    pub fn list() -> String {
        Self::ALL.map(MethodName::name).join(", ")
    }
}

impl fmt::Display for MethodName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl core::str::FromStr for MethodName {
    type Err = UnknownMethod;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        MethodName::parse(s)
    }
}

impl<'de> serde::Deserialize<'de> for MethodName {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        MethodName::parse(&s).map_err(serde::de::Error::custom)
    }
}

/// A parameter file's `method = "NAME"` must be the method it is read for
/// (`expected`).
pub fn check_file_method(found: &str, expected: &str, path: &Path) -> Result<(), ParamsFileError> {
    if found.trim() == expected {
        return Ok(());
    }
    let message = match MethodName::parse(found) {
        Ok(m) => format!(
            "`method` = \"{m}\" but the file is read for method `{expected}` (use --method {m} or remove the `method` line)"
        ),
        Err(e) => format!("`method` = \"{found}\": {e}"),
    };
    Err(ParamsFileError::Invalid {
        path: path.to_path_buf(),
        message,
    })
}

/// A method name limbfuse does not know.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown method `{0}`{hint}; available methods: {list}", hint = did_you_mean(.0), list = MethodName::list())]
pub struct UnknownMethod(pub String);

/// `; did you mean `NAME`?` for a name that differs from a method's only
/// in case or by at most two edits (a fresh-user audit, session 28:
/// `mjsl`, `MJLS`); empty otherwise.
fn did_you_mean(text: &str) -> String {
    let lower = text.trim().to_ascii_lowercase();
    let best = MethodName::ALL
        .into_iter()
        .map(|m| (edit_distance(&lower, m.name()), m))
        .min_by_key(|(d, _)| *d);
    match best {
        Some((d, m)) if d <= 2 && d < lower.chars().count() => {
            format!("; did you mean `{}`?", m.name())
        }
        _ => String::new(),
    }
}

/// Levenshtein distance (insertions, deletions, substitutions) of two
/// short strings, by characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (above + 1)
                .min(row[j] + 1)
                .min(diagonal + usize::from(ca != *cb));
            diagonal = above;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_parses_back_and_is_unique() {
        for m in MethodName::ALL {
            assert_eq!(MethodName::parse(m.name()), Ok(m));
        }
        let mut names: Vec<_> = MethodName::ALL.map(MethodName::name).to_vec();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), MethodName::ALL.len());
    }

    #[test]
    fn near_names_get_a_suggestion() {
        assert_eq!(edit_distance("mjsl", "mjls"), 2);
        assert_eq!(edit_distance("", "abc"), 3);
        for typo in ["mjsl", "MJLS", "Local", "globl", "knee-selfalgn"] {
            let e = MethodName::parse(typo).unwrap_err().to_string();
            assert!(e.contains("; did you mean `"), "{typo}: {e}");
        }
        let e = MethodName::parse("mjsl").unwrap_err().to_string();
        assert!(
            e.starts_with("unknown method `mjsl`; did you mean `mjls`?; available methods: "),
            "{e}"
        );
        let e = MethodName::parse("magic").unwrap_err().to_string();
        assert!(!e.contains("did you mean"), "{e}");
    }

    #[test]
    fn unknown_names_list_the_available_ones() {
        let e = MethodName::parse("magic").unwrap_err().to_string();
        assert!(e.contains("unknown method `magic`") && e.contains("gyro-integration"));
    }
}
