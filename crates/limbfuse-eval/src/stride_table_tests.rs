use super::*;

/// An estimate file of `method` over 0..6 s at 100 Hz with `columns`
/// (diagnostic names without `diag_`), the cells given as (column, time,
/// value), written to `dir`.
fn estimate_file(
    dir: &Path,
    method: &str,
    columns: &[&str],
    cells: &[(&str, f64, f64)],
) -> std::path::PathBuf {
    let path = dir.join(format!("{method}.csv"));
    // (`speed`, empty: an estimate file needs an estimate column)
    let mut text = format!("# method: {method}\nt,speed");
    for c in columns {
        text.push_str(&format!(",diag_{c}"));
    }
    text.push('\n');
    for k in 0..=600 {
        let t = f64::from(k) * 0.01;
        text.push_str(&format!("{t},"));
        for c in columns {
            let v = cells
                .iter()
                .find(|(n, at, _)| n == c && (at - t).abs() < 1e-9)
                .map(|x| x.2);
            text.push_str(&v.map_or_else(|| ",".to_string(), |v| format!(",{v}")));
        }
        text.push('\n');
    }
    std::fs::write(&path, text).unwrap();
    path
}

/// Two feet, the second left stride without a final contact: one row per
/// stride with its foot, back-dated start (decision row - time), the
/// final contact inside it or none, and no reference (no trial).
#[test]
fn stride_table_pairs_each_stride_with_its_contacts_per_foot() {
    let d = tempfile::tempdir().unwrap();
    let columns = [
        "ic_left",
        "fc_left",
        "ic_right",
        "fc_right",
        "stride_length_left",
        "stride_length_right",
        "stride_time_left",
        "stride_time_right",
    ];
    let cells = [
        // left: contacts at 1.0, 2.1, 3.2 (decided 0.1 s later), one final contact at 1.6
        ("ic_left", 1.1, 1.0),
        ("ic_left", 2.2, 2.1),
        ("ic_left", 3.3, 3.2),
        ("fc_left", 1.7, 1.6),
        ("stride_length_left", 2.3, 1.43),
        ("stride_time_left", 2.3, 1.1),
        ("stride_length_left", 3.4, 1.54),
        ("stride_time_left", 3.4, 1.1),
        // right: contacts at 1.5, 2.6, final contact at 2.0
        ("ic_right", 1.6, 1.5),
        ("ic_right", 2.7, 2.6),
        ("fc_right", 2.1, 2.0),
        ("stride_length_right", 2.8, 1.32),
        ("stride_time_right", 2.8, 1.1),
    ];
    let e = estimate_file(d.path(), "gait-events", &columns, &cells);
    let table = stride_table_of_files(None, &e, false, &TimeWindow::default()).unwrap();
    assert_eq!(table.method, "gait-events");
    let got: Vec<(StrideFoot, f64, Option<f64>, f64, f64)> = table
        .rows
        .iter()
        .map(|r| (r.foot, r.ic_s, r.fc_s, r.end_s, r.decided_s))
        .collect();
    let near = |a: f64, b: f64| (a - b).abs() < 1e-9;
    assert_eq!(got.len(), 3, "{got:?}");
    let expected = [
        (StrideFoot::Left, 1.0, Some(1.6), 2.1, 2.3),
        (StrideFoot::Right, 1.5, Some(2.0), 2.6, 2.8),
        (StrideFoot::Left, 2.1, None, 3.2, 3.4),
    ];
    for (g, x) in got.iter().zip(&expected) {
        assert_eq!(g.0, x.0, "{got:?}");
        assert!(
            near(g.1, x.1) && near(g.3, x.3) && near(g.4, x.4),
            "{got:?}"
        );
        assert_eq!(g.2.is_some(), x.2.is_some(), "{got:?}");
        assert!(g.2.zip(x.2).is_none_or(|(a, b)| near(a, b)), "{got:?}");
    }
    // stance: final contact - initial contact; swing: the next initial contact - final contact
    let phases: Vec<(Option<f64>, Option<f64>)> = table
        .rows
        .iter()
        .map(|r| (r.stance_time_s, r.swing_time_s))
        .collect();
    assert!(phases[0]
        .0
        .zip(phases[0].1)
        .is_some_and(|(a, b)| near(a, 0.6) && near(b, 0.5)));
    assert!(phases[1]
        .0
        .zip(phases[1].1)
        .is_some_and(|(a, b)| near(a, 0.5) && near(b, 0.6)));
    assert_eq!(phases[2], (None, None));
    let speeds: Vec<f64> = table.rows.iter().map(|r| r.speed_m_s.unwrap()).collect();
    assert!(near(speeds[0], 1.3) && near(speeds[1], 1.2) && near(speeds[2], 1.4));
    assert!(table
        .rows
        .iter()
        .all(|r| r.speed_ref_m_s.is_none() && r.ic_ref_s.is_none() && r.step_length_1_m.is_none()));
    let mut csv = Vec::new();
    table.write_csv(&mut csv).unwrap();
    let csv = String::from_utf8(csv).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], STRIDE_COLUMNS.join(","));
    assert_eq!(lines.len(), 4);
    // (the missing final contact, the stance and swing times it would give
    // and every reference are empty cells)
    assert!(
        lines[3].starts_with("left,2.1,,3.2,3.4,1.1,,,1.54,"),
        "{}",
        lines[3]
    );
    assert!(lines[3].ends_with(",,,,,"), "{}", lines[3]);
}

/// `lowback-speed`: a stride with a speed and the next one withheld (it
/// turns): both are rows, the withheld one without length or speed, each
/// with its two step lengths and its turn rate.
#[test]
fn stride_table_keeps_the_withheld_lowback_stride_without_a_speed() {
    let d = tempfile::tempdir().unwrap();
    let columns = [
        "ic",
        "step_length",
        "stride_length",
        "stride_time",
        "stride_turn_rate",
        "stride_withheld",
    ];
    let cells = [
        ("ic", 1.34, 1.0),
        ("ic", 1.84, 1.5),
        ("step_length", 1.84, 0.6),
        ("ic", 2.34, 2.0),
        ("step_length", 2.34, 0.65),
        ("stride_length", 2.34, 1.25),
        ("stride_time", 2.34, 1.0),
        ("stride_turn_rate", 2.34, 0.05),
        ("ic", 2.84, 2.5),
        ("step_length", 2.84, 0.7),
        ("stride_turn_rate", 2.84, -0.4),
        ("stride_withheld", 2.84, 1.0),
    ];
    let e = estimate_file(d.path(), "lowback-speed", &columns, &cells);
    let table = stride_table_of_files(None, &e, false, &TimeWindow::default()).unwrap();
    assert_eq!(table.rows.len(), 2, "{:?}", table.rows);
    let (a, b) = (&table.rows[0], &table.rows[1]);
    assert_eq!((a.foot, b.foot), (StrideFoot::Unknown, StrideFoot::Unknown));
    assert_eq!((a.ic_s, a.end_s, a.speed_m_s), (1.0, 2.0, Some(1.25)));
    assert_eq!(
        (a.step_length_1_m, a.step_length_2_m),
        (Some(0.6), Some(0.65))
    );
    assert_eq!((a.turn_rate_rad_s, a.speed_withheld), (Some(0.05), None));
    assert_eq!(
        (b.ic_s, b.end_s, b.speed_m_s, b.stride_length_m),
        (1.5, 2.5, None, None)
    );
    assert_eq!(
        (b.step_length_1_m, b.step_length_2_m),
        (Some(0.65), Some(0.7))
    );
    assert_eq!(b.turn_rate_rad_s, Some(-0.4));
    assert_eq!(b.speed_withheld, Some(SpeedWithheld::Turn));
    // (no final contacts: no stance or swing time)
    assert!(table
        .rows
        .iter()
        .all(|r| r.fc_s.is_none() && r.stance_time_s.is_none() && r.swing_time_s.is_none()));
}

/// An estimate of a method without strides is a clear error, not an empty table.
#[test]
fn stride_table_refuses_an_estimate_without_strides() {
    let d = tempfile::tempdir().unwrap();
    let e = estimate_file(d.path(), "mjls", &["sd_thigh"], &[]);
    let err = stride_table_of_files(None, &e, false, &TimeWindow::default()).unwrap_err();
    assert!(matches!(err, EvalError::NoStrides(_)), "{err}");
    assert!(err.to_string().contains("no stride columns"), "{err}");
}

/// A trial over 0..6 s at 100 Hz with `contact_left_ref` down over the
/// row ranges `stance` (`k0..k1`, row k at k/100 s), written to `dir`.
fn left_contact_trial(dir: &Path, stance: &[(u32, u32)]) -> std::path::PathBuf {
    let path = dir.join("trial.csv");
    let mut text = "# format: limbfuse-trial/1\nt,contact_left_ref\n".to_string();
    for k in 0..=600 {
        let down = stance.iter().any(|&(a, b)| (a..b).contains(&k));
        text.push_str(&format!("{},{}\n", f64::from(k) * 0.01, u8::from(down)));
    }
    std::fs::write(&path, text).unwrap();
    path
}

/// Known contacts, left foot: reference IC 1.00, 2.10, 3.20, 4.30 s and FC
/// 1.62, 2.72, 3.40 s; estimated IC 1.01, 2.12, 3.19, 4.31 and FC 1.60,
/// 2.75, 3.80 (the last 0.40 s from its reference: not paired). Each
/// stride's stance and swing times and their references are exact, the
/// third stride has no reference ones, and `evaluate` scores the first two:
/// stance errors -30, +10 ms; swing errors +40, -40 ms.
#[test]
fn stance_and_swing_times_come_from_the_paired_contacts() {
    let d = tempfile::tempdir().unwrap();
    let columns = [
        "ic_left",
        "fc_left",
        "stride_length_left",
        "stride_time_left",
    ];
    let cells = [
        ("ic_left", 1.11, 1.01),
        ("ic_left", 2.22, 2.12),
        ("ic_left", 3.29, 3.19),
        ("ic_left", 4.41, 4.31),
        ("fc_left", 1.7, 1.60),
        ("fc_left", 2.85, 2.75),
        ("fc_left", 3.9, 3.80),
        ("stride_length_left", 2.22, 1.4),
        ("stride_time_left", 2.22, 1.11),
        ("stride_length_left", 3.29, 1.4),
        ("stride_time_left", 3.29, 1.07),
        ("stride_length_left", 4.41, 1.4),
        ("stride_time_left", 4.41, 1.12),
    ];
    let e = estimate_file(d.path(), "gait-events", &columns, &cells);
    let trial = left_contact_trial(d.path(), &[(100, 162), (210, 272), (320, 340), (430, 601)]);
    let (ev, table) =
        evaluation_and_stride_table(Some(&trial), &e, false, &TimeWindow::default()).unwrap();
    let table = table.unwrap();
    let near = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(a), Some(b)) => (a - b).abs() < 1e-9,
        (a, b) => a.is_none() && b.is_none(),
    };
    // (stance, swing, fc_ref, stance_ref, swing_ref) per stride
    let expected = [
        (0.59, 0.52, Some(1.62), Some(0.62), Some(0.48)),
        (0.63, 0.44, Some(2.72), Some(0.62), Some(0.48)),
        (0.61, 0.51, None, None, None),
    ];
    assert_eq!(table.rows.len(), 3, "{:?}", table.rows);
    for (r, x) in table.rows.iter().zip(&expected) {
        let got = [
            r.stance_time_s,
            r.swing_time_s,
            r.fc_ref_s,
            r.stance_time_ref_s,
            r.swing_time_ref_s,
        ];
        let want = [Some(x.0), Some(x.1), x.2, x.3, x.4];
        for (g, w) in got.iter().zip(&want) {
            assert!(near(*g, *w), "{r:?}: {got:?} vs {want:?}");
        }
    }
    let s = &ev.stance_swing;
    assert_eq!(s.n_strides, 2, "{s:?}");
    assert!(near(s.stance_time_mae_ms, Some(20.0)), "{s:?}");
    assert!(near(s.stance_time_bias_ms, Some(-10.0)), "{s:?}");
    assert!(near(s.swing_time_mae_ms, Some(40.0)), "{s:?}");
    assert!(near(s.swing_time_bias_ms, Some(0.0)), "{s:?}");
    // the final contacts paired are those of the final-contact timing
    assert_eq!(ev.final_contact.as_ref().map(|f| f.n_matched), Some(2));
    let json = ev.to_json();
    assert_eq!(json["n_stance_swing"], 2);
    assert!((json["swing_time_mae_ms"].as_f64().unwrap() - 40.0).abs() < 1e-9);
    let mut csv = Vec::new();
    table.write_csv(&mut csv).unwrap();
    let csv = String::from_utf8(csv).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let first: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
    let cell = |name: &str| first[header.iter().position(|&h| h == name).unwrap()];
    assert_eq!(cell("fc_ref_s").parse::<f64>().unwrap(), 1.62);
    assert!((cell("stance_time_s").parse::<f64>().unwrap() - 0.59).abs() < 1e-9);
    assert!((cell("swing_time_ref_s").parse::<f64>().unwrap() - 0.48).abs() < 1e-9);
}
