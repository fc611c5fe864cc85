//! The shared recordings of `../shared/data` for the tests that run on
//! them (`LIMBFUSE_DATA` overrides the path; a test is skipped with a
//! message when a folder it needs is absent).

use std::path::{Path, PathBuf};

use limbfuse_core::Record;
use limbfuse_io::TrialReader;

/// The shared data folder, when every one of `folders` is in it.
pub fn data_dir(folders: &[&str]) -> Option<PathBuf> {
    let dir = std::env::var_os("LIMBFUSE_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"))
        });
    if folders.iter().all(|f| dir.join(f).is_dir()) {
        Some(dir)
    } else {
        println!("skipping: ../shared/data not found (set LIMBFUSE_DATA)");
        None
    }
}

/// Every record of the trial file at `path`.
pub fn read(path: &Path) -> Vec<Record> {
    let mut r = TrialReader::open(path).unwrap();
    let mut out = Vec::new();
    while let Some(rec) = r.next_record().unwrap() {
        out.push(rec);
    }
    out
}
