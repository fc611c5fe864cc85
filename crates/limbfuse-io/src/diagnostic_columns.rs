//! Which of a method's diagnostics an estimate file holds
//! (`limbfuse estimate --diagnostics all|none|NAME,...`; SPEC section 3:
//! the diagnostics are optional `diag_` columns after the estimated
//! quantities, which every reader finds by name).
//!
//! All of them by default. A user who wants only the angles (a controller
//! log, a cohort of long recordings) writes `none`, or names the ones
//! wanted; they keep the method's order whatever the order given.

use std::fmt;

use limbfuse_core::MAX_DIAG;

/// The diagnostic columns asked for.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum DiagnosticColumns {
    /// Every diagnostic of the method (the default).
    #[default]
    All,
    /// No diagnostic: `t` and the estimated quantities only.
    None,
    /// The named diagnostics (without or with their `diag_` prefix).
    Named(Vec<String>),
}

/// A `--diagnostics` value that names no diagnostic of the method.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("--diagnostics: `{name}` is not a diagnostic of `{method}` (its diagnostics: {available})")]
pub struct UnknownDiagnostic {
    /// The name given.
    pub name: String,
    /// The method.
    pub method: String,
    /// The method's diagnostics, comma-separated (`none` when it has none).
    pub available: String,
}

/// A `--diagnostics` value that is not `all`, `none` or a list of names.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("--diagnostics `{0}`: expected `all`, `none` or diagnostic names separated by commas")]
pub struct BadDiagnosticList(pub String);

impl DiagnosticColumns {
    /// Reads `all`, `none` or `NAME[,NAME...]` (a name may keep its
    /// `diag_` prefix; white space around names is ignored).
    pub fn parse(text: &str) -> Result<Self, BadDiagnosticList> {
        match text.trim() {
            "all" => return Ok(DiagnosticColumns::All),
            "none" => return Ok(DiagnosticColumns::None),
            _ => {}
        }
        let names: Vec<String> = text
            .split(',')
            .map(|n| n.trim())
            .map(|n| n.strip_prefix("diag_").unwrap_or(n).to_string())
            .collect();
        if names.iter().any(String::is_empty) {
            return Err(BadDiagnosticList(text.to_string()));
        }
        Ok(DiagnosticColumns::Named(names))
    }

    /// The indices (into `Estimate::diag`) of the columns to write, in the
    /// method's order, for a method whose diagnostics are `names`.
    pub fn resolve(&self, method: &str, names: &[&str]) -> Result<Vec<usize>, UnknownDiagnostic> {
        let n = names.len().min(MAX_DIAG);
        match self {
            DiagnosticColumns::All => Ok((0..n).collect()),
            DiagnosticColumns::None => Ok(Vec::new()),
            DiagnosticColumns::Named(wanted) => {
                for w in wanted {
                    if !names[..n].contains(&w.as_str()) {
                        return Err(UnknownDiagnostic {
                            name: w.clone(),
                            method: method.to_string(),
                            available: if n == 0 {
                                "none".into()
                            } else {
                                names[..n].join(", ")
                            },
                        });
                    }
                }
                Ok((0..n)
                    .filter(|&i| wanted.iter().any(|w| w == names[i]))
                    .collect())
            }
        }
    }
}

impl fmt::Display for DiagnosticColumns {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DiagnosticColumns::All => f.write_str("all"),
            DiagnosticColumns::None => f.write_str("none"),
            DiagnosticColumns::Named(n) => f.write_str(&n.join(",")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const NAMES: [&str; 4] = ["mode", "sd_trunk", "sd_thigh", "resets"];

    #[test]
    fn all_none_and_names_resolve_in_the_method_order() {
        let r = |t: &str| DiagnosticColumns::parse(t).unwrap().resolve("m", &NAMES);
        assert_eq!(r("all").unwrap(), vec![0, 1, 2, 3]);
        assert_eq!(r("none").unwrap(), Vec::<usize>::new());
        assert_eq!(r("resets, diag_sd_trunk").unwrap(), vec![1, 3]);
        assert_eq!(r("mode,mode").unwrap(), vec![0]);
        let e = r("sd_shank").unwrap_err();
        assert_eq!(e.name, "sd_shank");
        assert!(
            e.to_string().contains("mode, sd_trunk, sd_thigh, resets"),
            "{e}"
        );
        assert!(DiagnosticColumns::parse("mode,,resets").is_err());
        assert!(DiagnosticColumns::parse(" ").is_err());
        assert_eq!(DiagnosticColumns::default(), DiagnosticColumns::All);
    }
}
