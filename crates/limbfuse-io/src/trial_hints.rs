//! What to say when a path given as a trial is not one (a fresh-user
//! audit, session 28): a directory ("Is a directory (os error 21)"
//! before), or a raw recording that `limbfuse import` converts (the knee
//! rig's `LOG INTERVAL,...` log, a gaittoolbox sensor file: "missing
//! required column `t`" before, nothing about the importer).

use std::path::Path;

/// What follows "is a directory; a trial file is expected": the importer
/// of a gaittoolbox folder, the one trial file it holds, or its knee-rig
/// logs; empty otherwise.
pub(crate) fn directory_hint(dir: &Path) -> String {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return String::new();
    };
    let mut names: Vec<String> = entries
        .filter_map(Result::ok)
        .filter(|e| e.path().is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    if names
        .iter()
        .any(|n| n.starts_with("imu-") && n.ends_with(".csv"))
    {
        return format!(
            "; it holds a gaittoolbox recording (`imu-*.csv`): convert it with `limbfuse import \
             --format gaittoolbox {} -o trial.csv`",
            dir.display()
        );
    }
    let trials: Vec<&String> = names
        .iter()
        .filter(|n| n.ends_with(".csv") || n.ends_with(".arrow"))
        .collect();
    let rig_logs: Vec<&String> = trials
        .iter()
        .copied()
        .filter(|n| is_knee_rig_log(&dir.join(n)))
        .collect();
    if let Some(first) = rig_logs.first() {
        return format!(
            "; it holds {} raw knee-rig log{} ({first}{}): convert one with `limbfuse import \
             --format knee-rig {} -o trial.csv`",
            rig_logs.len(),
            if rig_logs.len() == 1 { "" } else { "s" },
            if rig_logs.len() > 1 { ", ..." } else { "" },
            dir.join(first).display()
        );
    }
    match trials.as_slice() {
        [one] => format!("; it holds {one}"),
        [] => String::new(),
        many => format!("; it holds {} .csv / .arrow files: give one", many.len()),
    }
}

/// Whether the file's first line is a knee-rig log's `LOG INTERVAL,...`.
fn is_knee_rig_log(path: &Path) -> bool {
    use std::io::Read;
    let mut head = [0u8; 16];
    std::fs::File::open(path)
        .and_then(|mut f| f.read(&mut head))
        .is_ok_and(|n| head[..n].starts_with(b"LOG INTERVAL"))
}

/// What to add to "missing required column `t`" when the header (its
/// first cell) is that of a raw recording an importer reads.
pub(crate) fn importer_hint(path: &Path, header: &[String]) -> String {
    let first = header.first().map_or("", |h| h.trim());
    if first == "LOG INTERVAL" {
        format!(
            "; this is a raw knee-rig log (`LOG INTERVAL,...` on its first line): convert it with \
             `limbfuse import --format knee-rig {} -o trial.csv`",
            path.display()
        )
    } else if first.starts_with("// fs=") {
        let folder = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        format!(
            "; this is a gaittoolbox sensor file (`// fs=...`): convert its folder with `limbfuse \
             import --format gaittoolbox {} -o trial.csv`",
            folder.display()
        )
    } else {
        String::new()
    }
}
