//! Brief C (session 28): the shared independent 1.2 m/s walk with the
//! shank's columns two rows (20 ms) late. Before: knee RMSE 26.0 deg
//! (knee-selfalign) and 25.7 (knee-gyro-axis), the accelerometer angle
//! untrusted and the zero the high-pass's. With `max_sensor_delay_s =
//! 0.05` the offset is found (`diag_sensor_delay_s` 0.02) and the RMSE,
//! allowing the output's documented latency of 2 samples (`--max-lag 3`),
//! is that of the synchronous walk (1.06 / 0.84).

use crate::s02_support::{evaluated_knee_rmse as knee_rmse, run_ok};
use crate::support::{edit_cells, shared_data};

#[test]
fn a_shank_two_rows_late_is_found_on_the_shared_walk() {
    let Some(path) = shared_data("independent-sim/walk-v1.2-s301.csv") else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let data: Vec<Vec<&str>> = text
        .lines()
        .skip_while(|l| !l.starts_with("t,"))
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let names: Vec<&str> = text
        .lines()
        .find(|l| l.starts_with("t,"))
        .unwrap()
        .split(',')
        .collect();
    let late = edit_cells(&text, |row, col, _| {
        if !(col.starts_with("shank_acc_") || col.starts_with("shank_gyr_")) {
            return None;
        }
        let c = names.iter().position(|n| *n == col).unwrap();
        Some(
            row.checked_sub(2)
                .map_or(String::new(), |r| data[r][c].to_string()),
        )
    });
    std::fs::write(d.path().join("late.csv"), late).unwrap();
    std::fs::write(d.path().join("delay.toml"), "max_sensor_delay_s = 0.05\n").unwrap();
    std::fs::write(
        d.path().join("delay-kga.toml"),
        "method = \"knee-gyro-axis\"\nmax_sensor_delay_s = 0.05\n",
    )
    .unwrap();
    for (method, params) in [
        ("knee-selfalign", "delay.toml"),
        ("knee-gyro-axis", "delay-kga.toml"),
    ] {
        run_ok(
            &["estimate", "--method", method, "late.csv", "-o", "off.csv"],
            d.path(),
        );
        let off = knee_rmse(
            d.path(),
            &["evaluate", "late.csv", "off.csv", "--max-lag", "3"],
        );
        run_ok(
            &[
                "estimate", "--method", method, "--params", params, "late.csv", "-o", "on.csv",
            ],
            d.path(),
        );
        let on = knee_rmse(
            d.path(),
            &["evaluate", "late.csv", "on.csv", "--max-lag", "3"],
        );
        let out = std::fs::read_to_string(d.path().join("on.csv")).unwrap();
        let mut lines = out.lines().filter(|l| !l.starts_with('#'));
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let col = header
            .iter()
            .position(|h| *h == "diag_sensor_delay_s")
            .expect("diag_sensor_delay_s column");
        let last: f64 = lines
            .next_back()
            .unwrap()
            .split(',')
            .nth(col)
            .unwrap()
            .parse()
            .unwrap();
        eprintln!(
            "{method}: knee RMSE {off:.3} deg without the search, {on:.3} with; delay {last} s"
        );
        assert!((last - 0.02).abs() < 1e-6, "{method}: delay {last}");
        assert!(on < 1.5, "{method}: {on} deg ({off} without the search)");
        assert!(off > 10.0, "{method}: {off} deg without the search");
    }
}
