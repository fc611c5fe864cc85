//! Twenty-seventh session's generalisation audit: `lowback-speed` on time
//! stamps with a receiver's jitter (the samples uniform, the stamps not).

use crate::support::{edit_cells, limbfuse, shared_data};

/// Stride speed MAE (m/s) of `lowback-speed` on `dir/j.csv`.
fn speed_mae(dir: &std::path::Path) -> f64 {
    let o = limbfuse(
        &[
            "estimate",
            "--method",
            "lowback-speed",
            "j.csv",
            "-o",
            "e.csv",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = limbfuse(&["evaluate", "j.csv", "e.csv", "--json"], dir);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    v["speed_mae_mps"].as_f64().unwrap()
}

/// The HA001 straight walk (0.028 m/s stride speed MAE as recorded). The
/// period was the first time step alone: the first stamp moved by 3 ms gave
/// 0.287 m/s (every speed scaled by the squared ratio of periods), and a
/// +-2 ms jitter on every stamp 0.169. The period is now the mean step.
#[test]
fn lowback_speed_takes_the_mean_period() {
    let Some(walk) = shared_data("mobgap-lowerback/HA001-test5-trial1.csv") else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(walk).unwrap();
    // (deterministic jitter within +-2 ms: the rows are 10 ms apart)
    let jitter = |row: usize| ((row * 7919) % 5) as f64 * 1e-3 - 2e-3;
    for (name, shift) in [
        (
            "first stamp 3 ms early",
            &(|row: usize| if row == 0 { -3e-3 } else { 0.0 }) as &dyn Fn(usize) -> f64,
        ),
        ("every stamp within +-2 ms", &jitter),
    ] {
        let edited = edit_cells(&text, |row, column, cell| {
            (column == "t").then(|| format!("{}", cell.parse::<f64>().unwrap() + shift(row)))
        });
        std::fs::write(d.path().join("j.csv"), edited).unwrap();
        let mae = speed_mae(d.path());
        eprintln!("{name}: stride speed MAE {mae:.3} m/s");
        assert!(mae < 0.035, "{name}: {mae} m/s");
    }
}
