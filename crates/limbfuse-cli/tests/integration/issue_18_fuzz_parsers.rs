//! Issue 18 item 3: fuzz-style tests of the parsers a user's files reach:
//! every method's parameter file (its `limbfuse params` text with values
//! replaced by adversarial ones, lines uncommented, dropped or repeated,
//! bytes inserted) and the trial CSV reader (a real simulated trial with
//! bytes flipped, inserted, removed or the file cut short).
//!
//! Asserted: never a panic; a refused file is a typed error whose message
//! names the file; a parameter file that is accepted builds an estimator or
//! is refused by it, and the estimator runs 3 s of walking with outputs that
//! are finite or missing. The cases run in CI are bounded (`CASES`); a
//! longer search: `LIMBFUSE_FUZZ_CASES=5000 cargo test --release -p limbfuse-cli --test integration
//! -- issue_18_fuzz_parsers::`.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::process::Command;

use limbfuse_core::Record;
use limbfuse_io::{TrialLayout, TrialMeta, TrialReader};
use limbfuse_methods::{build, default_params_file, MethodFlags, MethodName, MethodSpec};
use proptest::prelude::*;

/// Cases per property in CI (`LIMBFUSE_FUZZ_CASES` overrides).
fn cases() -> u32 {
    std::env::var("LIMBFUSE_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(64)
}

/// Values a mistyped or hostile parameter file may hold.
const HOSTILE: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "-1e308",
    "1e308",
    "0",
    "-1",
    "-0.0",
    "1e-320",
    "9223372036854775807",
    "-9223372036854775808",
    "\"\"",
    "\"x\"",
    "[]",
    "[nan]",
    "[1e308, -1e308, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]",
    "true",
    "{}",
    "2026-12-02",
    "'''\n'''",
];

/// A 6 s simulated walking trial (the binary writes it once), read whole.
fn walking() -> &'static (String, TrialMeta, TrialLayout, Vec<Record>) {
    static TRIAL: std::sync::OnceLock<(String, TrialMeta, TrialLayout, Vec<Record>)> =
        std::sync::OnceLock::new();
    TRIAL.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("walk.csv");
        let out = Command::new(env!("CARGO_BIN_EXE_limbfuse"))
            .args([
                "simulate",
                "walking",
                "--duration",
                "6",
                "--seed",
                "3",
                "-o",
            ])
            .arg(&path)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = std::fs::read_to_string(&path).unwrap();
        let mut r = TrialReader::open(&path).unwrap();
        let (meta, layout) = (r.meta().clone(), *r.layout());
        let mut records = Vec::new();
        while let Some(rec) = r.next_record().unwrap() {
            records.push(rec);
        }
        (text, meta, layout, records)
    })
}

#[derive(Debug, Clone)]
enum LineEdit {
    /// Uncomment the line if commented and put a hostile value after `=`.
    Value(usize, usize),
    Drop(usize),
    Repeat(usize),
    /// Insert these bytes (lossily decoded) at this fraction of the text.
    Bytes(u16, Vec<u8>),
}

fn line_edit() -> impl Strategy<Value = LineEdit> {
    prop_oneof![
        4 => (any::<usize>(), 0..HOSTILE.len()).prop_map(|(l, v)| LineEdit::Value(l, v)),
        1 => any::<usize>().prop_map(LineEdit::Drop),
        1 => any::<usize>().prop_map(LineEdit::Repeat),
        1 => (any::<u16>(), proptest::collection::vec(any::<u8>(), 1..6))
            .prop_map(|(p, b)| LineEdit::Bytes(p, b)),
    ]
}

/// Applies `edit`; the key whose value it replaced (and a plain value,
/// which may be a path) goes to `keys`.
fn apply(text: &str, edit: &LineEdit, keys: &mut Vec<String>) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let n = lines.len();
    if n == 0 {
        return text.to_string();
    }
    match edit {
        LineEdit::Value(l, v) => {
            // The first line with a `=` from the chosen one on.
            if let Some(k) = (0..n)
                .map(|k| (l % n + k) % n)
                .find(|&k| lines[k].contains('='))
            {
                let line = lines[k].trim_start().trim_start_matches('#').trim_start();
                let key = line.split('=').next().unwrap_or("").trim().to_string();
                lines[k] = format!("{key} = {}", HOSTILE[*v]);
                keys.push(key);
                // A path value (`library = "x"`) may be named instead.
                let value = HOSTILE[*v].trim_matches('"');
                if value.chars().all(char::is_alphanumeric) && !value.is_empty() {
                    keys.push(value.to_string());
                }
            }
        }
        LineEdit::Drop(l) => {
            lines.remove(l % n);
        }
        LineEdit::Repeat(l) => {
            let line = lines[l % n].clone();
            lines.insert(l % n, line);
        }
        LineEdit::Bytes(at, bytes) => {
            let mut s = lines.join("\n");
            let mut i = (*at as usize * s.len()) / (u16::MAX as usize + 1);
            while !s.is_char_boundary(i) {
                i -= 1;
            }
            s.insert_str(i, &String::from_utf8_lossy(bytes));
            return s;
        }
    }
    lines.join("\n")
}

/// Resolves, builds and runs `method` with parameter file `text`; a refusal
/// must name the file or one of the `edited` keys, or be the refusal of the
/// unedited file (`imm-bslip` without `--library`).
fn exercise(method: MethodName, text: &str, edited: &[String]) -> Result<(), String> {
    let path = Path::new("fuzz.toml");
    let resolve =
        |t: &str| MethodSpec::from_parts(method, Some((t, path)), &MethodFlags::default());
    let spec = match resolve(text) {
        Ok(s) => s,
        Err(e) => {
            let m = e.to_string();
            let unedited = resolve(&default_params_file(method))
                .err()
                .map(|e| e.to_string());
            return if m.contains("fuzz.toml")
                || edited.iter().any(|k| m.contains(k.as_str()))
                || unedited.as_deref() == Some(m.as_str())
            {
                Ok(())
            } else {
                Err(format!("the error names neither the file nor the key: {m}"))
            };
        }
    };
    let (_, meta, layout, records) = walking();
    let Ok(mut est) = build(&spec, meta, layout) else {
        return Ok(());
    };
    for rec in records.iter().take(300) {
        let Ok(e) = est.step(&rec.sample) else {
            continue;
        };
        let finite = |v: &Option<f64>| v.is_none_or(f64::is_finite);
        if !(e.segment.iter().all(finite) && e.joint.iter().all(finite) && finite(&e.speed)) {
            return Err(format!("non-finite output at t = {}: {e:?}", rec.sample.t));
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    #[test]
    fn issue_18_parameter_files_never_panic(
        m in 0..MethodName::ALL.len(),
        edits in proptest::collection::vec(line_edit(), 1..4),
    ) {
        let method = MethodName::ALL[m];
        let mut text = default_params_file(method);
        let mut keys = Vec::new();
        for e in &edits {
            text = apply(&text, e, &mut keys);
        }
        let r = catch_unwind(AssertUnwindSafe(|| exercise(method, &text, &keys)));
        match r {
            Ok(Ok(())) => {}
            Ok(Err(why)) => prop_assert!(false, "{}: {why}\n--- file ---\n{text}", method.name()),
            Err(_) => prop_assert!(false, "{} panicked on\n--- file ---\n{text}", method.name()),
        }
    }

    #[test]
    fn issue_18_mutated_trial_files_never_panic(
        cut in any::<u16>(),
        edits in proptest::collection::vec((any::<u16>(), 0u8..3, any::<u8>()), 1..8),
    ) {
        let (text, ..) = walking();
        // The header and the first 40 rows: every column kind, short enough.
        let end = text.match_indices('\n').nth(text.lines().take_while(|l| l.starts_with('#')).count() + 40)
            .map_or(text.len(), |(i, _)| i + 1);
        let mut bytes = text.as_bytes()[..end].to_vec();
        for (at, kind, b) in &edits {
            let i = (*at as usize * bytes.len()) / (u16::MAX as usize + 1);
            match kind {
                0 => bytes[i] = *b,
                1 => bytes.insert(i, *b),
                _ => { bytes.remove(i); }
            }
        }
        bytes.truncate(bytes.len() - (cut as usize % 64).min(bytes.len()));
        let r = catch_unwind(AssertUnwindSafe(|| {
            let mut reader = TrialReader::from_reader(Path::new("mutated.csv"), Box::new(std::io::Cursor::new(bytes.clone())))?;
            while reader.next_record()?.is_some() {}
            Ok::<(), limbfuse_io::FileError>(())
        }));
        match r {
            Ok(Ok(())) => {}
            Ok(Err(e)) => prop_assert!(e.to_string().starts_with("mutated.csv"), "{e}"),
            Err(_) => prop_assert!(false, "the reader panicked on\n{}", String::from_utf8_lossy(&bytes)),
        }
    }
}

/// The classes the fuzzing found, kept as plain regression tests.
#[test]
fn issue_18_fuzz_corpus() {
    let run = |m: &str, text: &str| {
        let method = MethodName::parse(m).unwrap();
        catch_unwind(AssertUnwindSafe(|| exercise(method, text, &[]))).expect("no panic")
    };
    let refusal = |m: &str, text: &str| {
        let method = MethodName::parse(m).unwrap();
        MethodSpec::from_parts(
            method,
            Some((text, Path::new("fuzz.toml"))),
            &MethodFlags::default(),
        )
        .map(|_| ())
        .unwrap_err()
        .to_string()
    };
    // `lowback-speed` reported its bad values as method `gait-events`,
    // without the file.
    let m = refusal("lowback-speed", "leg_length = nan");
    assert!(
        m.contains("fuzz.toml") && m.contains("lowback-speed") && m.contains("leg_length"),
        "{m}"
    );
    // `rmx` accepted a NaN Mahony gain and wrote NaN knee angles.
    let m = refusal("rmx", "[rmx]\nkp = nan");
    assert!(m.contains("fuzz.toml") && m.contains("kp"), "{m}");
    // A finite but absurd gain diverges: the output is missing, not NaN.
    run("rmx", "[rmx]\nkp = 1e308").unwrap();
    // An empty library path was reported as ": No such file or directory".
    let m = refusal("imm-bslip", "library = \"\"");
    assert!(m.contains("fuzz.toml") && m.contains("library"), "{m}");
}
