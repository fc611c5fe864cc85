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

/// What a header row shows of a file of another format given as a CSV
/// table, or `None`. Audits: a gait library given as a trial was
/// "duplicate column `rest_length:1.0`" (2026-12-05, now "a JSON file"); an
/// FES model or a parameter file (`.toml`) was "a JSON file" (its `[model]`
/// line) or "missing required column `t`" (its `key = value` line).
pub(crate) fn other_format(path: &Path, header: &[String]) -> Option<&'static str> {
    let first = header.first()?.trim();
    let one_cell = header.len() == 1;
    let toml_extension = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    let bare_key = |k: &str| {
        !k.is_empty()
            && k.chars()
                .all(|c| c.is_ascii_alphanumeric() || "_-.\"".contains(c))
    };
    // `[model]`, `[[segments]]`; `key = value`
    let table_header = first.len() > 2
        && first.starts_with('[')
        && first.ends_with(']')
        && bare_key(first.trim_matches(|c| c == '[' || c == ']').trim());
    let key_value = first
        .split_once('=')
        .is_some_and(|(k, _)| bare_key(k.trim()));
    if one_cell && (toml_extension || table_header || key_value) {
        Some("a TOML file (e.g. a parameter file or an FES model)")
    } else if first.starts_with('{') || first.starts_with('[') {
        Some("a JSON file (e.g. a gait library)")
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::other_format;
    use std::path::Path;

    fn of(path: &str, line: &str) -> Option<&'static str> {
        let header: Vec<String> = line.split(',').map(str::to_string).collect();
        other_format(Path::new(path), &header)
    }

    #[test]
    fn toml_json_and_csv_headers_are_told_apart() {
        let toml = Some("a TOML file (e.g. a parameter file or an FES model)");
        let json = Some("a JSON file (e.g. a gait library)");
        assert_eq!(of("m.toml", "[model]"), toml);
        assert_eq!(of("m.txt", "[model]"), toml);
        assert_eq!(of("m.txt", "[[segments]]"), toml);
        assert_eq!(of("p.txt", "method = \"mjls\""), toml);
        assert_eq!(of("p.toml", "anything"), toml);
        assert_eq!(of("lib.json", "{\"format\": 1"), json);
        assert_eq!(of("lib.json", "[1.0"), json);
        assert_eq!(of("a.json", "[{\"a\": 1}]"), json);
        assert_eq!(of("w.csv", "t,thigh_gyr_x"), None);
        assert_eq!(of("w.toml", "t,thigh_gyr_x"), None);
        assert_eq!(of("w.csv", "t"), None);
    }
}
