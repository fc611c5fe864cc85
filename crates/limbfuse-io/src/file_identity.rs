//! Whether two paths name one file, before either exists: an output that
//! names an input would replace it (`limbfuse_io::AtomicFile` renames over
//! whatever is there). Used by the CLI's output checks and by the Python
//! package's `report`.

use std::path::{Path, PathBuf};

/// `path` as the file it names: its canonical path when it exists,
/// otherwise its canonical parent directory joined with its name (so
/// `./c.csv` and `c.csv` are one file before either is written). `None`
/// for `-` (standard input or output) or a path whose directory does not
/// exist (said later, when it is opened).
pub fn resolved(path: &Path) -> Option<PathBuf> {
    if path.as_os_str() == "-" {
        return None;
    }
    if let Ok(p) = path.canonicalize() {
        return Some(p);
    }
    let parent = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    Some(parent.canonicalize().ok()?.join(path.file_name()?))
}

/// Whether `a` and `b` name the same file ([`resolved`]).
pub fn same_file(a: &Path, b: &Path) -> bool {
    matches!((resolved(a), resolved(b)), (Some(x), Some(y)) if x == y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_file_by_any_name_before_it_exists() {
        let d = tempfile::tempdir().unwrap();
        let a = d.path().join("x.csv");
        let b = d.path().join(".").join("x.csv");
        assert!(same_file(&a, &b));
        std::fs::write(&a, "t\n").unwrap();
        assert!(same_file(&a, &b));
        assert!(!same_file(&a, &d.path().join("y.csv")));
        assert!(!same_file(Path::new("-"), Path::new("-")));
        assert!(!same_file(
            &d.path().join("no/such/x.csv"),
            &d.path().join("no/such/x.csv")
        ));
    }
}
