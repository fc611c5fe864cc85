//! `fusion = "rate-bias"` (2026-12-06): `knee-selfalign`'s relative
//! gyro-bias state, a limbfuse extension beside paper 002's Algorithm 1
//! (docs/KNEE_SELFALIGN.md "Fusion"), reachable from a parameter file. On
//! the shared independent 1.2 m/s walk the paper's one-state fusion leaves a
//! relative gyro bias as a lag (knee RMSE 1.06 deg as shipped, 5.96 deg
//! with 0.05 rad/s added to the shank's z rate); the rate-bias state takes
//! it up (0.25 and 0.86 deg).

use crate::s02_support::{evaluated_knee_rmse as knee_rmse, run_ok};
use crate::support::{edit_cells, shared_data};

#[test]
fn the_rate_bias_fusion_takes_up_a_gyro_bias_on_the_shared_walk() {
    let Some(path) = shared_data("independent-sim/walk-v1.2-s301.csv") else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let biased = edit_cells(&text, |_, col, cell| {
        (col == "shank_gyr_z").then(|| format!("{}", cell.parse::<f64>().unwrap() + 0.05))
    });
    std::fs::write(d.path().join("walk.csv"), &text).unwrap();
    std::fs::write(d.path().join("biased.csv"), biased).unwrap();
    std::fs::write(d.path().join("rb.toml"), "fusion = \"rate-bias\"\n").unwrap();
    let mut rmse = Vec::new();
    for trial in ["walk.csv", "biased.csv"] {
        for params in [None, Some("rb.toml")] {
            let mut args = vec![
                "estimate",
                "--method",
                "knee-selfalign",
                trial,
                "-o",
                "k.csv",
            ];
            args.extend(params.map(|p| ["--params", p]).into_iter().flatten());
            run_ok(&args, d.path());
            rmse.push(knee_rmse(d.path(), &["evaluate", trial, "k.csv"]));
        }
    }
    // [paper, rate-bias] as shipped, then with the bias added.
    let [paper, rate_bias, paper_biased, rate_bias_biased] = rmse[..] else {
        unreachable!()
    };
    assert!(paper > 0.9 && rate_bias < 0.35, "{rmse:?}");
    assert!(paper_biased > 5.0 && rate_bias_biased < 1.0, "{rmse:?}");
}
