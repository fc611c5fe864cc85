//! A fresh-user audit (session 28), item 9: flags and metadata keys that
//! differed between commands for the same thing (aliases added, nothing
//! removed).

use std::path::Path;
use std::process::Output;

use crate::support::limbfuse;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn ok(args: &[&str], dir: &Path) -> Output {
    let o = limbfuse(args, dir);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    o
}

/// `demo` took only `--out`; `-o` / `--output` (every other command's
/// output flag) were "unexpected argument". Now both name the demo's
/// directory (the run stops at a bad `--speed`, after creating it).
#[test]
fn demo_takes_o_and_output_for_its_directory() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    for (flag, dir) in [("-o", "d1"), ("--output", "d2"), ("--out", "d3")] {
        let o = limbfuse(&["demo", flag, dir, "--speed", "99"], p);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{e}");
        assert!(!e.contains("unexpected argument"), "{flag}: {e}");
        assert!(p.join(dir).is_dir(), "{flag}: {e}");
    }
}

/// `simulate walking|knee|calibration` took `--imu-rate` only, knee-fes and
/// fixed-hip `--rate` as well; `--rate` is now accepted by all.
#[test]
fn simulate_takes_rate_as_an_alias_of_imu_rate() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    for (what, extra) in [
        ("walking", &["--duration", "2"][..]),
        ("knee", &["--duration", "2"]),
        ("calibration", &["--poses", "2"]),
    ] {
        let mut args = vec!["simulate", what, "--rate", "50", "-o", "s.csv"];
        args.extend_from_slice(extra);
        ok(&args, p);
        let text = std::fs::read_to_string(p.join("s.csv")).unwrap();
        assert!(text.contains("# sample_rate_hz: 50\n"), "{what}");
    }
}

/// `simulate calibration --force`'s help spoke of a `--duration` the
/// subcommand does not have; it now names what makes its length.
#[test]
fn simulate_calibration_force_help_names_its_own_flags() {
    let d = tempfile::tempdir().unwrap();
    let o = ok(&["simulate", "calibration", "--help"], d.path());
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(!help.contains("--duration"), "{help}");
    assert!(help.contains("--poses x (--hold + --transition)"), "{help}");
}

/// A copy of `from` with `lines` added after its first line.
fn with_metadata(dir: &Path, from: &str, to: &str, lines: &[&str]) {
    let text = std::fs::read_to_string(dir.join(from)).unwrap();
    let (first, rest) = text.split_once('\n').unwrap();
    let mut out = format!("{first}\n");
    for l in lines {
        out += &format!("# {l}\n");
    }
    out += rest;
    std::fs::write(dir.join(to), out).unwrap();
}

/// `lowback-speed` read `# leg_length:` only, `imm-bslip` `# leg_length_m:`
/// only. Each now reads both (its own first); both stated with different
/// values: a warning, and the method's own key wins.
#[test]
fn leg_length_metadata_is_read_under_either_key() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &["simulate", "walking", "--duration", "12", "-o", "w.csv"],
        p,
    );
    with_metadata(p, "w.csv", "m.csv", &["leg_length_m: 0.95"]);
    let o = ok(
        &[
            "estimate",
            "--method",
            "lowback-speed",
            "m.csv",
            "-o",
            "e.csv",
        ],
        p,
    );
    assert!(
        stderr(&o).contains("pendulum length 0.95 m from the trial's `# leg_length_m:`"),
        "{}",
        stderr(&o)
    );
    with_metadata(
        p,
        "w.csv",
        "both.csv",
        &["leg_length_m: 0.95", "leg_length: 0.85"],
    );
    let o = ok(
        &[
            "estimate",
            "--method",
            "lowback-speed",
            "both.csv",
            "-o",
            "e.csv",
        ],
        p,
    );
    let e = stderr(&o);
    assert!(
        e.contains("pendulum length 0.85 m from the trial's `# leg_length:`"),
        "{e}"
    );
    // (once: review 28 found the warning printed twice)
    assert_eq!(
        e.matches("warning: both.csv states `# leg_length: 0.85` and `# leg_length_m: 0.95`")
            .count(),
        1,
        "{e}"
    );

    ok(
        &[
            "gait-library",
            "build",
            "--speeds",
            "0.7:0.7:0.1",
            "-o",
            "lib.json",
        ],
        p,
    );
    ok(
        &[
            "simulate",
            "bslip",
            "--speed",
            "0.7",
            "--library",
            "lib.json",
            "--duration",
            "2",
            "-o",
            "b.csv",
        ],
        p,
    );
    with_metadata(p, "b.csv", "bl.csv", &["leg_length: 0.95"]);
    let o = ok(
        &[
            "estimate",
            "--method",
            "imm-bslip",
            "--library",
            "lib.json",
            "bl.csv",
            "-o",
            "i.csv",
        ],
        p,
    );
    let e = stderr(&o);
    assert!(
        e.contains("l0 0.95 m") && e.contains("from # body_mass_kg / # leg_length,"),
        "{e}"
    );
    with_metadata(
        p,
        "b.csv",
        "bb.csv",
        &["leg_length: 0.95", "leg_length_m: 0.9"],
    );
    let o = ok(
        &[
            "estimate",
            "--method",
            "imm-bslip",
            "--library",
            "lib.json",
            "bb.csv",
            "-o",
            "i.csv",
        ],
        p,
    );
    let e = stderr(&o);
    assert!(e.contains("l0 0.9 m"), "{e}");
    assert!(
        e.contains("`imm-bslip` reads `# leg_length_m:`, its own key"),
        "{e}"
    );
}
