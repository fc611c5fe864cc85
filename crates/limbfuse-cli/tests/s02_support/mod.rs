//! What the tests on the shared gaittoolbox S02 walk need: its folder (or a
//! skip message when `../shared/data` is absent) and a `limbfuse` run that
//! must succeed.

use std::path::{Path, PathBuf};

use crate::support::limbfuse;

/// `../shared/data/gaittoolbox-s02-walk` (or under `LIMBFUSE_DATA`); `None`
/// with a message when it is absent.
pub fn s02_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("LIMBFUSE_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"))
        });
    let s02 = dir.join("gaittoolbox-s02-walk");
    if s02.is_dir() {
        Some(s02)
    } else {
        println!("skipping: ../shared/data/gaittoolbox-s02-walk not found (set LIMBFUSE_DATA)");
        None
    }
}

/// Runs `limbfuse args` in `dir`, asserts exit 0, returns its stdout.
pub fn run_ok(args: &[&str], dir: &Path) -> Vec<u8> {
    let o = limbfuse(args, dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o.stdout
}
