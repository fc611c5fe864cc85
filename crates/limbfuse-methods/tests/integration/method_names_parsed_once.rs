//! Issue 13: no string comparison on method names outside the one parser
//! (`MethodName::parse` in `limbfuse-methods/src/name.rs`). Every other
//! decision about a method is a `match` on `MethodName`.

use std::path::{Path, PathBuf};

use limbfuse_methods::MethodName;

fn rust_sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            // Tests may name methods to drive the binary; benches too.
            let skip = matches!(
                p.file_name().and_then(|n| n.to_str()),
                Some("tests" | "benches" | "target")
            );
            if !skip {
                rust_sources(&p, out);
            }
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// `path:line: text` of every comparison of a method name with a string.
fn comparisons(files: &[PathBuf]) -> Vec<String> {
    let mut hits = Vec::new();
    for f in files {
        if f.ends_with("limbfuse-methods/src/name.rs") {
            continue;
        }
        let text = std::fs::read_to_string(f).unwrap();
        let mut in_tests = false;
        for (i, line) in text.lines().enumerate() {
            if line.trim_start().starts_with("#[cfg(test)]") {
                in_tests = true;
            }
            if in_tests || line.trim_start().starts_with("//") {
                continue;
            }
            for m in MethodName::ALL {
                let q = format!("\"{}\"", m.name());
                let patterns = [
                    format!("== {q}"),
                    format!("!= {q}"),
                    format!("{q} =="),
                    format!("{q} =>"),
                    format!("{q} |"),
                    format!("| {q}"),
                    format!("Some({q})"),
                    format!("&[{q}"),
                    format!("[{q},"),
                ];
                if patterns.iter().any(|p| line.contains(p.as_str())) {
                    hits.push(format!("{}:{}: {}", f.display(), i + 1, line.trim()));
                }
            }
        }
    }
    hits
}

fn workspace_crates() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

#[test]
fn no_method_name_is_compared_as_a_string_outside_the_parser() {
    let mut files = Vec::new();
    rust_sources(&workspace_crates(), &mut files);
    assert!(files.len() > 50, "found only {} sources", files.len());
    let hits = comparisons(&files);
    assert!(
        hits.is_empty(),
        "method names compared as strings (use MethodName):\n{}",
        hits.join("\n")
    );
}

#[test]
fn the_scan_finds_a_comparison_when_there_is_one() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("bad.rs");
    std::fs::write(&f, "fn f(m: &str) -> bool { m == \"global\" }\n").unwrap();
    assert_eq!(comparisons(&[f]).len(), 1);
}
