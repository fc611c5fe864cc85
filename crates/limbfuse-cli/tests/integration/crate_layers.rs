//! Issue 13: the crates form a stack; each depends (normal dependencies)
//! only on crates below it, in this order, as docs/ARCHITECTURE.md draws.

use std::path::Path;

/// Bottom to top; crates in one layer (the two front ends, the `limbfuse`
/// binary and the Python package of `python/`) may not depend on each other.
const LAYERS: [&[&str]; 12] = [
    &["limbfuse-core"],
    &["limbfuse-models"],
    &["limbfuse-estimators"],
    &["limbfuse-sim"],
    &["limbfuse-io"],
    &["limbfuse-signal"],
    &["limbfuse-methods"],
    &["limbfuse-eval"],
    &["limbfuse-report"],
    &["limbfuse-workflows"],
    &["limbfuse-studies"],
    &["limbfuse-cli", "limbfuse-py"],
];

/// The layer of a crate.
fn layer(name: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&name))
}

/// The `limbfuse-*` names under `[dependencies]` of a manifest.
fn normal_dependencies(manifest: &str) -> Vec<String> {
    let mut in_deps = false;
    let mut out = Vec::new();
    for line in manifest.lines() {
        let l = line.trim();
        if l.starts_with('[') {
            in_deps = l == "[dependencies]";
            continue;
        }
        if in_deps && l.starts_with("limbfuse-") {
            let name: String = l
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
                .collect();
            out.push(name);
        }
    }
    out
}

fn violations(crate_name: &str, deps: &[String]) -> Vec<String> {
    let Some(me) = layer(crate_name) else {
        return vec![format!("{crate_name} is not in LAYERS")];
    };
    deps.iter()
        .filter(|d| layer(d).is_none_or(|k| k >= me))
        .map(|d| format!("{crate_name} depends on {d}, which is not below it"))
        .collect()
}

#[test]
fn every_crate_depends_only_on_crates_below_it() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut seen = 0;
    let mut bad = Vec::new();
    for e in std::fs::read_dir(&crates).unwrap().flatten() {
        let manifest = e.path().join("Cargo.toml");
        let Ok(text) = std::fs::read_to_string(&manifest) else {
            continue;
        };
        let name = e.file_name().to_string_lossy().into_owned();
        bad.extend(violations(&name, &normal_dependencies(&text)));
        seen += 1;
    }
    // The Python package: its own cargo workspace (python/Cargo.toml).
    let py = std::fs::read_to_string(crates.join("../python/Cargo.toml")).unwrap();
    bad.extend(violations("limbfuse-py", &normal_dependencies(&py)));
    seen += 1;
    assert_eq!(
        seen,
        LAYERS.iter().map(|l| l.len()).sum::<usize>(),
        "a crate was added or removed: update LAYERS"
    );
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn a_dependency_upwards_is_found() {
    let deps = normal_dependencies(
        "[dependencies]\nlimbfuse-eval.workspace = true\n[dev-dependencies]\nlimbfuse-cli = {}\n",
    );
    assert_eq!(deps, ["limbfuse-eval"]);
    assert_eq!(violations("limbfuse-io", &deps).len(), 1);
    assert!(violations("limbfuse-workflows", &deps).is_empty());
    // The two front ends sit side by side: neither may call the other.
    let cli = ["limbfuse-cli".to_string()];
    assert_eq!(violations("limbfuse-py", &cli).len(), 1);
    assert!(violations("limbfuse-py", &deps).is_empty());
}
