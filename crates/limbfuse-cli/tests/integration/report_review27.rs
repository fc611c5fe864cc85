//! `limbfuse report`, review 27: the initial contacts of `lowback-speed`,
//! the knee-axis panel of `knee-gyro-axis`, the CoM velocity as the IMM
//! speed plot's reference on B-SLIP trials, and plot titles that fit their
//! plots (`plot-fes-sd`'s ran past the right edge).

use std::path::Path;

use crate::cli_report::{by_id, parse, series_of};
use crate::support::limbfuse;

/// Runs `limbfuse args` in `dir`, which must succeed.
fn ok(args: &[&str], dir: &Path) {
    let o = limbfuse(args, dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "limbfuse {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

fn read(dir: &Path, name: &str) -> String {
    std::fs::read_to_string(dir.join(name)).expect("written")
}

/// The `d` of the path of `series` in plot `id`.
fn path_of(html: &str, id: &str, series: &str) -> String {
    let start = html.find(&format!(r#"id="{id}""#)).expect("the plot");
    let plot = &html[start..start + html[start..].find("</svg></svg>").expect("its end")];
    let rest = plot
        .split(&format!(r#"data-series="{series}""#))
        .nth(1)
        .expect("the series");
    let d = rest.split(r#"d=""#).nth(1).expect("its path");
    d[..d.find('"').unwrap()].to_string()
}

/// Spikes of a path `M x y l dx dy dx dy ...` (integers, a `-` may follow
/// a digit) that leaves 0 and comes back: half its vertical moves.
fn spikes(d: &str) -> usize {
    spike_depths(d).len()
}

/// A `lowback-speed` estimate of a simulated walk with gait references:
/// its initial contacts (`diag_ic`, scored in the events table) were not
/// drawn, only its speed. The events panel now has `plot-initial-contacts`:
/// the reference contacts (`contact_*_ref` 0 -> 1) up, the estimate's down.
#[test]
fn report_draws_the_initial_contacts_of_lowback_speed() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &[
            "simulate",
            "walking",
            "--duration",
            "20",
            "--gait-reference",
            "-o",
            "w.csv",
        ],
        p,
    );
    ok(
        &[
            "estimate",
            "--method",
            "lowback-speed",
            "w.csv",
            "-o",
            "lb.csv",
        ],
        p,
    );
    ok(&["report", "w.csv", "lb.csv", "-o", "r.html"], p);
    let html = read(p, "r.html");
    by_id(&parse(&html), "plot-initial-contacts");
    assert_eq!(series_of(&html, "plot-initial-contacts"), ["ref", "e0"]);
    // Each line goes up (reference) or down (estimate) from 0 and back:
    // two vertical moves of the path per spike (20 s at 100 Hz: no
    // decimation), as many on the estimate's line as it has contacts.
    let n_ic = read(p, "lb.csv")
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .filter(|l| !l.split(',').nth(2).unwrap_or("").is_empty())
        .count();
    assert!(n_ic > 20, "{n_ic} contacts in 20 s");
    assert_eq!(spikes(&path_of(&html, "plot-initial-contacts", "e0")), n_ic);
    let reference = spikes(&path_of(&html, "plot-initial-contacts", "ref"));
    assert!(reference > 20, "{reference} reference contacts in 20 s");
    // Without the estimate's contacts (`--diagnostics none`) there is no
    // such plot.
    ok(
        &[
            "estimate",
            "--method",
            "lowback-speed",
            "w.csv",
            "--diagnostics",
            "none",
            "-o",
            "lb0.csv",
        ],
        p,
    );
    ok(&["report", "w.csv", "lb0.csv", "-o", "r0.html"], p);
    assert!(!read(p, "r0.html").contains(r#"id="plot-initial-contacts""#));
}

/// `knee-gyro-axis` (the inner `knee-selfalign`'s axes) had no knee-axis
/// panel: it wrote no `diag_j_*`. It now writes the axes in use, and the
/// report draws them as for `knee-selfalign`.
#[test]
fn report_has_the_knee_axis_panel_of_knee_gyro_axis() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&["simulate", "knee", "--duration", "20", "-o", "k.csv"], p);
    ok(
        &[
            "estimate",
            "--method",
            "knee-gyro-axis",
            "k.csv",
            "-o",
            "kg.csv",
        ],
        p,
    );
    ok(&["report", "k.csv", "kg.csv", "-o", "r.html"], p);
    let html = read(p, "r.html");
    let tags = parse(&html);
    for id in [
        "panel-knee-0",
        "plot-knee-axis-thigh-0",
        "plot-knee-axis-shank-0",
        "plot-knee-axis-change-0",
    ] {
        by_id(&tags, id);
    }
    assert_eq!(series_of(&html, "plot-knee-axis-thigh-0"), ["x", "y", "z"]);
}

/// The IMM speed plot of a B-SLIP trial (CoM velocity `com_vx`, no
/// `speed_ref`) had no reference line; `com_vx` is now drawn as it,
/// labelled so.
#[test]
fn imm_speed_plot_has_com_vx_as_reference() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &[
            "gait-library",
            "build",
            "--speeds",
            "0.6:0.8:0.1",
            "-o",
            "lib.json",
        ],
        p,
    );
    ok(
        &[
            "simulate",
            "bslip",
            "--library",
            "lib.json",
            "--speed",
            "0.7",
            "--duration",
            "4",
            "-o",
            "b.csv",
        ],
        p,
    );
    assert!(!read(p, "b.csv").contains("speed_ref"));
    ok(
        &[
            "estimate",
            "--method",
            "imm-bslip",
            "--library",
            "lib.json",
            "b.csv",
            "-o",
            "e.csv",
        ],
        p,
    );
    ok(&["report", "b.csv", "e.csv", "-o", "r.html"], p);
    let html = read(p, "r.html");
    let series = series_of(&html, "plot-imm-speed-0");
    assert!(series.contains(&"reference".to_string()), "{series:?}");
    assert!(html.contains("com_vx (forward CoM velocity, reference)"));
}

/// Every plot title of a knee-FES report with sdre and ekf fits its plot:
/// `plot-fes-sd`'s title was a 150-character sentence, clipped at the
/// right edge (the plot is 900 px wide, the title starts at 64 px, 13 px
/// bold: about 110 characters fit). The explanation is in the panel note.
#[test]
fn fes_plot_titles_fit_their_plots() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(
        &["simulate", "knee-fes", "--duration", "10", "-o", "f.csv"],
        p,
    );
    for m in ["sdre", "ekf"] {
        ok(
            &[
                "estimate",
                "--method",
                m,
                "f.csv",
                "-o",
                &format!("{m}.csv"),
            ],
            p,
        );
    }
    ok(
        &["report", "f.csv", "sdre.csv", "ekf.csv", "-o", "r.html"],
        p,
    );
    let html = read(p, "r.html");
    by_id(&parse(&html), "plot-fes-sd");
    let titles: Vec<&str> = html
        .split(r#"<text class="title""#)
        .skip(1)
        .map(|s| {
            let s = &s[s.find('>').unwrap() + 1..];
            &s[..s.find("</text>").unwrap()]
        })
        .collect();
    assert!(titles.len() >= 4, "{titles:?}");
    for t in titles {
        assert!(t.chars().count() <= 100, "too long for its plot: {t}");
    }
    assert!(
        html.contains("Riccati solution of sdre"),
        "the note explains P_11"
    );
}

/// Session 48: the initial-contacts plot tells the feet of `lowback-speed`'s
/// contacts by the spike's depth (right 1, left 0.6, not told 0.3), as its
/// `diag_ic_right` / `diag_ic_left` give them, and the reference's by its
/// height. HA001 test5 trial2 (10.8 s, no decimation): 11 contacts, 4 told
/// right, 5 left, 2 not told (within 2 s of the start or the end).
#[test]
fn report_draws_the_feet_of_lowback_contacts() {
    let Some(data) = crate::cli_gait_events::data_dir() else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let trial = data.join("mobgap-lowerback/HA001-test5-trial2.csv");
    let trial = trial.to_str().unwrap();
    ok(
        &[
            "estimate",
            "--method",
            "lowback-speed",
            trial,
            "-o",
            "lb.csv",
        ],
        p,
    );
    ok(&["report", trial, "lb.csv", "-o", "r.html"], p);
    let html = read(p, "r.html");
    let count = |name: &str| crate::cli_gait_events::diag_values(&p.join("lb.csv"), name).len();
    let (right, left, all) = (count("ic_right"), count("ic_left"), count("ic"));
    assert!(
        right > 2 && left > 2 && all > right + left,
        "{right} {left} {all}"
    );
    // Depths of the estimate's spikes (pixels), deepest first.
    let mut depths = spike_depths(&path_of(&html, "plot-initial-contacts", "e0"));
    depths.sort_unstable_by(|a, b| b.cmp(a));
    assert_eq!(depths.len(), all);
    let deepest = depths[0] as f64;
    let near = |x: i64, f: f64| (x as f64 - f * deepest).abs() <= 1.0;
    assert_eq!(depths.iter().filter(|&&x| near(x, 1.0)).count(), right);
    assert_eq!(depths.iter().filter(|&&x| near(x, 0.6)).count(), left);
    assert_eq!(
        depths.iter().filter(|&&x| near(x, 0.3)).count(),
        all - right - left
    );
    let title = crate::report_audit_28::title_of(&html, "plot-initial-contacts");
    assert!(title.contains("right foot 1, left 0.6"), "{title}");
}

/// The depth (pixels) of each spike of a path (`spikes`' format): the first
/// vertical move of each pair.
fn spike_depths(d: &str) -> Vec<i64> {
    let mut moves: Vec<i64> = vec![];
    for segment in d.split('M').skip(1) {
        let Some((_, rel)) = segment.split_once('l') else {
            continue;
        };
        let numbers: Vec<i64> = rel
            .replace('-', " -")
            .split_whitespace()
            .map(|v| v.parse().expect("an integer"))
            .collect();
        moves.extend(numbers.iter().skip(1).step_by(2).filter(|dy| **dy != 0));
    }
    moves.chunks_exact(2).map(|m| m[0].abs()).collect()
}
