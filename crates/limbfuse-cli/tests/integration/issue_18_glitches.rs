//! Issue 18 item 1: one corrupted cell (a bus glitch far beyond any sensor's
//! range) must not ruin the rest of a trial. Before the range gate, a single
//! thigh gyro cell of 1e300 left `mjls`, `global` and `local` ~91 deg off
//! for the rest of the trial, and nothing was reported.

use std::path::Path;
use std::process::Output;

use crate::support::limbfuse;

fn assert_ok(o: &Output) {
    assert_eq!(
        o.status.code(),
        Some(0),
        "stderr: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// A copy of trial `from` with the cell (`row` after the header, `column`)
/// replaced by `value`.
fn corrupt(dir: &Path, from: &str, to: &str, cells: &[(usize, &str, &str)]) {
    let text = std::fs::read_to_string(dir.join(from)).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let header = lines.iter().position(|l| l.starts_with("t,")).unwrap();
    let cols: Vec<String> = lines[header].split(',').map(str::to_string).collect();
    for (row, column, value) in cells {
        let c = cols.iter().position(|x| x == column).unwrap();
        let mut fields: Vec<String> = lines[header + 1 + row]
            .split(',')
            .map(str::to_string)
            .collect();
        fields[c] = value.to_string();
        lines[header + 1 + row] = fields.join(",");
    }
    std::fs::write(dir.join(to), lines.join("\n") + "\n").unwrap();
}

/// Column `name` of an estimate file, from data row `from` on.
fn column(dir: &Path, file: &str, name: &str, from: usize) -> Vec<f64> {
    let text = std::fs::read_to_string(dir.join(file)).unwrap();
    let mut rows = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = rows.next().unwrap().split(',').collect();
    let c = header.iter().position(|h| *h == name).unwrap();
    rows.skip(from)
        .map(|l| l.split(',').nth(c).unwrap().parse().unwrap())
        .collect()
}

#[test]
fn issue_18_one_glitched_cell_does_not_ruin_the_rest_of_the_trial() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    assert_ok(&limbfuse(
        &[
            "simulate",
            "walking",
            "--duration",
            "20",
            "--seed",
            "5",
            "-o",
            "clean.csv",
        ],
        p,
    ));
    corrupt(
        p,
        "clean.csv",
        "glitch.csv",
        &[
            (800, "thigh_gyr_z", "1e300"),
            (1200, "shank_acc_x", "-1e308"),
        ],
    );
    for method in ["mjls", "global", "local"] {
        for trial in ["clean", "glitch"] {
            let o = limbfuse(
                &[
                    "estimate",
                    "--method",
                    method,
                    &format!("{trial}.csv"),
                    "-o",
                    &format!("{trial}-{method}.csv"),
                ],
                p,
            );
            assert_ok(&o);
            let err = String::from_utf8_lossy(&o.stderr);
            if trial == "glitch" {
                assert!(
                    err.contains("1 gyroscope, 1 accelerometer and 0 encoder reading(s) were rejected (first at t = 8 s)"),
                    "{err}"
                );
            } else {
                assert!(!err.contains("were rejected"), "{err}");
            }
        }
        for seg in ["thigh", "shank"] {
            let a = column(p, &format!("clean-{method}.csv"), seg, 800);
            let b = column(p, &format!("glitch-{method}.csv"), seg, 800);
            let worst = a
                .iter()
                .zip(&b)
                .map(|(x, y)| (x - y).abs().to_degrees())
                .fold(0.0, f64::max);
            // One missing update moves the estimate by a fraction of a degree.
            assert!(worst < 0.5, "{method} {seg}: {worst} deg after the glitch");
        }
        let rejected = column(p, &format!("glitch-{method}.csv"), "diag_rejected_gyro", 0);
        assert_eq!(rejected[799], 0.0);
        assert_eq!(rejected[800], 1.0);
        assert_eq!(*rejected.last().unwrap(), 1.0);
    }
}

#[test]
fn issue_18_sensor_range_comes_from_the_trial_metadata_and_a_bad_one_is_an_error() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    assert_ok(&limbfuse(
        &["simulate", "walking", "--duration", "5", "-o", "w.csv"],
        p,
    ));
    let text = std::fs::read_to_string(p.join("w.csv")).unwrap();
    // A 1 rad/s gyro range: walking thigh rates exceed it, so readings go.
    std::fs::write(
        p.join("narrow.csv"),
        format!("# gyro_range_rad_s: 1\n{text}"),
    )
    .unwrap();
    let o = limbfuse(
        &["estimate", "--method", "mjls", "narrow.csv", "-o", "n.csv"],
        p,
    );
    assert_ok(&o);
    assert!(String::from_utf8_lossy(&o.stderr).contains("gyroscope"));
    let rejected = column(p, "n.csv", "diag_rejected_gyro", 0);
    assert!(*rejected.last().unwrap() > 100.0, "{:?}", rejected.last());

    std::fs::write(p.join("bad.csv"), format!("# acc_range_m_s2: -3\n{text}")).unwrap();
    let o = limbfuse(
        &["estimate", "--method", "mjls", "bad.csv", "-o", "b.csv"],
        p,
    );
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("acc_range_m_s2: -3") && err.contains("positive number"),
        "{err}"
    );
    assert!(!p.join("b.csv").exists());
}

/// The shared independent walking trial, or `None` (with a message) when
/// `../shared/data` is absent.
fn independent_walk() -> Option<std::path::PathBuf> {
    let dir = std::env::var_os("LIMBFUSE_DATA")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| {
            std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"))
        });
    let f = dir.join("independent-sim/walk-v1.2-s301.csv");
    if f.is_file() {
        Some(f)
    } else {
        println!("skipping: ../shared/data not found (set LIMBFUSE_DATA)");
        None
    }
}

/// The RMSEs (deg) of the rows `names` of `limbfuse evaluate trial estimate`.
fn rmse_rows<const N: usize>(
    dir: &Path,
    trial: &str,
    estimate: &str,
    names: [&str; N],
) -> [f64; N] {
    let o = limbfuse(&["evaluate", trial, estimate], dir);
    assert_ok(&o);
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    names.map(|name| {
        let line = text
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name))
            .unwrap_or_else(|| panic!("no {name} row in {text}"));
        line.split_whitespace().nth(1).unwrap().parse().unwrap()
    })
}

/// The four segment RMSEs (deg) of `limbfuse evaluate trial estimate`.
fn segment_rmse(dir: &Path, trial: &str, estimate: &str) -> [f64; 4] {
    rmse_rows(dir, trial, estimate, ["trunk", "thigh", "shank", "foot"])
}

/// Issue 18 done-when: one 1e300 gyro cell, one -1e308 accelerometer cell,
/// a burst of 50 saturated gyro samples (2000 deg/s on the thigh's z axis
/// while x and y move on) and a stuck thigh gyroscope (its three axes
/// frozen for 2 s) each leave every segment's RMSE within 0.5 deg of the
/// clean run's, for local, mjls, global and chain, and the rejections are
/// reported. Before the plausibility checks the saturated burst cost the
/// thigh 750-800 deg of RMSE (the filters integrated 35 rad/s for 0.5 s).
#[test]
fn issue_18_glitches_within_range_saturation_and_a_stuck_gyro_leave_the_rmse() {
    let Some(walk) = independent_walk() else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::copy(&walk, p.join("clean.csv")).unwrap();
    // rows after the header; the trial is 100 Hz
    corrupt(
        p,
        "clean.csv",
        "gyro1e300.csv",
        &[(2000, "thigh_gyr_z", "1e300")],
    );
    corrupt(
        p,
        "clean.csv",
        "acc1e308.csv",
        &[(3000, "shank_acc_x", "-1e308")],
    );
    let saturated: Vec<(usize, &str, &str)> = (2500..2550)
        .map(|r| (r, "thigh_gyr_z", "34.906585"))
        .collect();
    corrupt(p, "clean.csv", "saturated.csv", &saturated);
    let text = std::fs::read_to_string(p.join("clean.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let header = lines.iter().position(|l| l.starts_with("t,")).unwrap();
    let cols: Vec<&str> = lines[header].split(',').collect();
    let frozen: Vec<String> = ["thigh_gyr_x", "thigh_gyr_y", "thigh_gyr_z"]
        .iter()
        .map(|c| {
            let k = cols.iter().position(|x| x == c).unwrap();
            lines[header + 1 + 4000]
                .split(',')
                .nth(k)
                .unwrap()
                .to_string()
        })
        .collect();
    let mut stuck = Vec::new();
    for r in 4000..4200 {
        for (c, v) in ["thigh_gyr_x", "thigh_gyr_y", "thigh_gyr_z"]
            .iter()
            .zip(&frozen)
        {
            stuck.push((r, *c, v.as_str()));
        }
    }
    corrupt(p, "clean.csv", "stuck.csv", &stuck);
    // (trial, gyroscope readings that must be rejected, accelerometer ones)
    let cases = [
        ("gyro1e300", 1, 0),
        ("acc1e308", 0, 1),
        ("saturated", 50, 0),
        ("stuck", 190, 0),
    ];
    for method in ["local", "mjls", "global", "chain"] {
        let est = |trial: &str| {
            let o = limbfuse(
                &[
                    "estimate",
                    "--method",
                    method,
                    &format!("{trial}.csv"),
                    "-o",
                    &format!("{trial}-{method}.csv"),
                ],
                p,
            );
            assert_ok(&o);
            String::from_utf8_lossy(&o.stderr).to_string()
        };
        let err = est("clean");
        assert!(!err.contains("were rejected"), "{method} clean: {err}");
        let clean = segment_rmse(p, "clean.csv", &format!("clean-{method}.csv"));
        for (trial, gyro, acc) in cases {
            let err = est(trial);
            // (mjls's encoder gate may refuse a row while the thigh is
            // carried by the chain: the encoder count is not fixed here)
            let reported = format!("{gyro} gyroscope, {acc} accelerometer and ");
            assert!(
                err.contains(&reported) && err.contains("were rejected"),
                "{method} {trial}: {err}"
            );
            let rmse = segment_rmse(p, &format!("{trial}.csv"), &format!("{trial}-{method}.csv"));
            for (k, (a, b)) in clean.iter().zip(&rmse).enumerate() {
                assert!(
                    (b - a).abs() <= 0.5,
                    "{method} {trial} segment {k}: RMSE {b} deg vs clean {a} deg"
                );
            }
        }
    }
}

/// `walk` copied into `dir` as `clean.csv`, and as `to` with ten single
/// +-3 rad/s spikes, 0.9-1.3 s apart from row `first` (100 Hz), on
/// `columns` in turn (spike `k` positive when `positive(k)`).
fn spiked_copy(
    dir: &Path,
    walk: &Path,
    (to, first): (&str, usize),
    columns: &[&str],
    positive: fn(usize) -> bool,
) {
    std::fs::copy(walk, dir.join("clean.csv")).unwrap();
    let text = std::fs::read_to_string(dir.join("clean.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let header = lines.iter().position(|l| l.starts_with("t,")).unwrap();
    let cols: Vec<&str> = lines[header].split(',').collect();
    let cell = |row: usize, column: &str| -> f64 {
        let k = cols.iter().position(|x| *x == column).unwrap();
        let line = lines[header + 1 + row];
        line.split(',').nth(k).unwrap().parse().unwrap()
    };
    let spikes: Vec<(usize, &str, String)> = (0..10)
        .map(|k| {
            let row = first + 97 * k + 11 * (k % 4);
            let column = columns[k % columns.len()];
            let sign = if positive(k) { 3.0 } else { -3.0 };
            (row, column, format!("{}", cell(row, column) + sign))
        })
        .collect();
    let cells: Vec<(usize, &str, &str)> = spikes
        .iter()
        .map(|(r, c, v)| (*r, *c, v.as_str()))
        .collect();
    corrupt(dir, "clean.csv", to, &cells);
}

/// Runs `estimate --method method [--params params] trial.csv` in `dir` and
/// checks what its warning says was rejected: `Some(0)` no warning at all,
/// `Some(n)` exactly `n` gyroscope readings and nothing else, `None` no
/// gyroscope reading (other rejections allowed). Returns the output's name.
fn estimate_with_rejections(
    dir: &Path,
    method: &str,
    trial: &str,
    params: Option<&str>,
    gyroscope: Option<u32>,
) -> String {
    let out = format!("{trial}-{method}-{}.csv", params.unwrap_or("default"));
    let input = format!("{trial}.csv");
    let mut args = vec!["estimate", "--method", method, &input, "-o", &out];
    if let Some(f) = params {
        args.extend(["--params", f]);
    }
    let o = limbfuse(&args, dir);
    assert_ok(&o);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    match gyroscope {
        Some(0) => assert!(!err.contains("were rejected"), "{method}, {trial}: {err}"),
        Some(n) => assert!(
            err.contains(&format!(
                ": {n} gyroscope, 0 accelerometer and 0 encoder reading(s) were rejected"
            )),
            "{method}, {trial}: {err}"
        ),
        None => assert!(
            !err.contains("were rejected") || err.contains(": 0 gyroscope,"),
            "{method}, {trial}: {err}"
        ),
    }
    out
}

/// Session 41 (docs/CHAIN.md, "Gyroscope rows beside an encoder"): single
/// +-3 rad/s gyroscope spikes, inside the range and the jump bound, on the
/// shared independent walk with encoders. Before, `chain` applied them, its
/// encoder gate then refused the (right) encoders and re-adopted them with
/// the spikes' error (sixty spikes: mean RMSE 0.205 -> 1.002 deg); now the
/// spikes are refused and the rest of the trial is as clean.
#[test]
fn issue_18_chain_refuses_gyro_spikes_beside_an_encoder() {
    let Some(walk) = independent_walk() else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    // ten spikes, 0.9-1.3 s apart from 15 s, on the thigh, shank and foot in turn
    spiked_copy(
        p,
        &walk,
        ("spikes.csv", 1500),
        &["thigh_gyr_z", "shank_gyr_z", "foot_gyr_z"],
        |k| k % 2 == 0,
    );
    let mut rmse = Vec::new();
    for (trial, refused) in [("clean", 0), ("spikes", 10)] {
        let out = estimate_with_rejections(p, "chain", trial, None, Some(refused));
        rmse.push(segment_rmse(p, &format!("{trial}.csv"), &out));
    }
    for (k, (a, b)) in rmse[0].iter().zip(&rmse[1]).enumerate() {
        assert!(
            (b - a).abs() <= 0.01,
            "segment {k}: {b} deg with the spikes, {a} clean"
        );
    }
}

/// Session 49 (docs/ROBUST_INPUT.md, "Gyroscope spikes beside the
/// encoders"): the same kind of spikes made `mjls` refuse the knee or ankle
/// encoder that contradicted the moved segment until the 0.5 s lockout
/// restarted it (sixty spikes: seven restarts, knee RMSE 0.086 -> 0.963
/// deg). Now `mjls` and `global` replace each spike by the rate the
/// encoders imply (thigh, shank) or hold the segment's rate over them (foot);
/// `rate_spike_test = false` applies them as before.
#[test]
fn issue_18_mjls_and_global_replace_gyro_spikes_the_encoders_contradict() {
    let Some(walk) = independent_walk() else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    // ten spikes, 0.9-1.3 s apart from 15 s, on the thigh, shank and foot in turn
    spiked_copy(
        p,
        &walk,
        ("spikes.csv", 1500),
        &["thigh_gyr_z", "shank_gyr_z", "foot_gyr_z"],
        |k| k % 2 == 1,
    );
    std::fs::write(p.join("off.toml"), "rate_spike_test = false\n").unwrap();
    for method in ["mjls", "global"] {
        let mut rmse = Vec::new();
        for (trial, params, refused) in [
            ("clean", None, Some(0)),
            ("spikes", None, Some(10)),
            ("spikes", Some("off.toml"), None),
        ] {
            let out = estimate_with_rejections(p, method, trial, params, refused);
            rmse.push(segment_rmse(p, &format!("{trial}.csv"), &out));
        }
        eprintln!("{method}: segment RMSE clean / spikes / spikes without the test: {rmse:?}");
        let worst = |k: usize| {
            (0..4)
                .map(|s| (rmse[k][s] - rmse[0][s]).abs())
                .fold(0.0, f64::max)
        };
        assert!(worst(1) <= 0.03, "{method}: {rmse:?}");
        assert!(
            worst(2) > 0.1,
            "{method}: the spikes must matter without the test: {rmse:?}"
        );
    }
}

/// Session 47 (docs/KNEE_SELFALIGN.md, "Gyroscope spikes"): ten single
/// +-3 rad/s spikes on the thigh and shank gyroscopes of the shared
/// independent walk, inside the range and the jump bound. Eq 3 takes the
/// rate derivative, which turns each spike into four errors of 25-200
/// rad/s^2; the knee methods fitted the sensor positions through them,
/// stopped trusting the accelerometer angle and drifted (knee RMSE 1.06 ->
/// 6.01 deg, `knee-gyro-axis` 0.84 -> 47.2). Now the window's gross eq-3
/// outliers are left out of the fit and of the accelerometer angle
/// (`knee_selfalign::position_outliers`): within 0.3 deg of the clean run
/// (1.25 and 1.07 deg: each spike still adds 1.7 deg to the gyroscope
/// angle until the accelerometer angle corrects it), and `estimate` says
/// how many samples were left out (`diag_position_outliers`). The same
/// spikes from 1 s, in the first window (no geometry to screen at before
/// the fit they pull): `knee-selfalign` 8.08 deg with the residual screen
/// alone, nothing left out; 1.14 / 1.08 with the fit-free pre-screen
/// (`mark_rate_spikes`) giving the screen a robust start.
#[test]
fn knee_methods_leave_gyro_spikes_out_of_the_position_fit() {
    let Some(walk) = independent_walk() else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    // ten spikes, 0.9-1.3 s apart from 15 s, on the thigh and shank in turn;
    // the same from 1 s, in the first window, which has no geometry before it
    let columns = ["thigh_gyr_z", "shank_gyr_z"];
    spiked_copy(p, &walk, ("spikes.csv", 1500), &columns, |k| k % 3 == 0);
    spiked_copy(p, &walk, ("first.csv", 100), &columns, |k| k % 3 == 0);
    let rmse: Vec<(&str, f64, f64, f64)> = ["knee-selfalign", "knee-gyro-axis"]
        .into_iter()
        .map(|method| {
            let [clean, spiked, first] = ["clean", "spikes", "first"].map(|trial| {
                let out = format!("{trial}-{method}.csv");
                let o = limbfuse(
                    &[
                        "estimate",
                        "--method",
                        method,
                        &format!("{trial}.csv"),
                        "-o",
                        &out,
                    ],
                    p,
                );
                assert_ok(&o);
                let rmse = rmse_rows(p, &format!("{trial}.csv"), &out, ["knee"])[0];
                println!("{method} {trial}: knee RMSE {rmse:.3} deg");
                // the summary says how many samples the screens left out
                let said = String::from_utf8_lossy(&o.stderr)
                    .contains("left out of the sensor-position fits as gross outliers");
                assert_eq!(said, trial != "clean", "{method} {trial}");
                rmse
            });
            (method, clean, spiked, first)
        })
        .collect();
    for (method, clean, spiked, first) in rmse {
        for (when, with) in [("from 15 s", spiked), ("from 1 s", first)] {
            assert!(
                with - clean <= 0.3,
                "{method}: {with} deg with the spikes {when}, {clean} clean"
            );
        }
    }
}

/// Session 49 (docs/ROBUST_INPUT.md, "Gyroscope spikes in the FES
/// filters"): single shank gyroscope spikes within the range and the jump
/// bound were measurements the continuous FES filters took at face value
/// (thirty +-3 rad/s spikes on the shared P2-R trial: `sdre` 0.073 -> 18.5
/// deg knee RMSE after 1 s). Now each is replaced by the median of the last
/// three accepted readings, and the knee is the clean run's.
#[test]
fn issue_18_fes_filters_replace_shank_gyro_spikes() {
    let Some(trial) = independent_walk().map(|w| w.with_file_name("fes-P2-R-s900.csv")) else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    // ten spikes, 0.9-1.3 s apart from 5 s, on the shank gyroscope
    spiked_copy(p, &trial, ("spikes.csv", 500), &["shank_gyr_z"], |k| {
        k % 3 != 0
    });
    for method in ["sdre", "ekf", "knee-kinematic"] {
        let mut rmse = Vec::new();
        for (t, refused) in [("clean", 0), ("spikes", 10)] {
            let out = estimate_with_rejections(p, method, t, None, Some(refused));
            rmse.push(rmse_rows(p, &format!("{t}.csv"), &out, ["knee"])[0]);
        }
        eprintln!("{method}: knee RMSE clean / spikes {rmse:?}");
        assert!((rmse[1] - rmse[0]).abs() <= 0.01, "{method}: {rmse:?}");
    }
}

/// Session 50 (docs/ROBUST_INPUT.md 2r): a single foot gyroscope spike in
/// stance was a swing for `gait-events` (its toe off the rest's noise
/// trough, the stance's real toe off lost), one in late swing an initial
/// contact. Ten +-3 rad/s spikes on the sagittal axes of the shared gaitmap
/// walk's feet, 0.4-0.6 s apart from 7.3 s: 1 extra initial contact, 2
/// missed and 3 extra final contacts before; now a contact change decided
/// on one reading waits for the next, which reverses a spike's, and the
/// events are the clean walk's.
#[test]
fn issue_18_gait_events_ignore_foot_gyro_spikes() {
    let Some(data) = crate::cli_gait_events::data_dir() else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let walk = data.join("gaitmap-foot-walk/trial.csv");
    let columns = ["foot_gyr_z", "foot_left_gyr_z"];
    spiked_copy(p, &walk, ("spikes.csv", 1500), &columns, |k| k % 3 != 0);
    let [clean, spiked] = ["clean", "spikes"].map(|t| {
        let v =
            crate::cli_gait_events::evaluate_json("gait-events", &p.join(format!("{t}.csv")), p);
        std::fs::copy(p.join("e.csv"), p.join(format!("{t}-ge.csv"))).unwrap();
        v
    });
    for kind in ["initial_contact", "final_contact"] {
        for figure in ["missed", "extra", "n_matched"] {
            assert_eq!(
                spiked[kind][figure], clean[kind][figure],
                "{kind} {figure}: {spiked}"
            );
        }
    }
    // every event where it was, each written on its row or the next: the
    // spikes move the foot's medio-lateral axis (a principal component of
    // the moving gyroscope) a little, and the events' interpolated times
    // with it (by 0.3 ms at most here, a sample being 4.9 ms)
    let events = |t: &str| -> Vec<(String, f64)> {
        let text = std::fs::read_to_string(p.join(format!("{t}-ge.csv"))).unwrap();
        let mut rows = text.lines().skip_while(|l| !l.starts_with("t,"));
        let header: Vec<&str> = rows.next().unwrap().split(',').collect();
        let columns: Vec<usize> = (0..header.len())
            .filter(|&k| header[k].starts_with("diag_ic_") || header[k].starts_with("diag_fc_"))
            .collect();
        rows.flat_map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            columns
                .iter()
                .filter(|&&k| !cells[k].is_empty())
                .map(|&k| (header[k].to_string(), cells[k].parse::<f64>().unwrap()))
                .collect::<Vec<_>>()
        })
        .collect()
    };
    let (clean, spiked) = (events("clean"), events("spikes"));
    assert_eq!(clean.len(), spiked.len(), "{clean:?}\n{spiked:?}");
    for (c, s) in clean.iter().zip(&spiked) {
        assert!(
            c.0 == s.0 && (c.1 - s.1).abs() < 1e-3,
            "{c:?} clean, {s:?} with spikes"
        );
    }
}
