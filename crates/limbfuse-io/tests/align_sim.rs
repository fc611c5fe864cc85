//! Alignment on simulated walking with random mountings.

use limbfuse_core::{Record, Segment};
use limbfuse_io::align::{estimate_alignment, AlignOptions};
use limbfuse_sim::{Mounting, WalkingConfig, WalkingSimulator};
use nalgebra::{Matrix3, Vector3};

fn sim(cfg: WalkingConfig) -> (Vec<Record>, [Matrix3<f64>; 4]) {
    let s = WalkingSimulator::new(cfg).unwrap();
    let m = [0, 1, 2, 3].map(|i| s.imus()[i].mount);
    (s.collect(), m)
}

#[test]
fn explore() {
    let mut stats = [[0.0f64; 4]; 4];
    for seed in 0..8u64 {
        for speed in [0.6, 1.0, 1.5] {
            let oop = std::env::var_os("NO_OOP").is_none();
            let cfg = WalkingConfig {
                seed,
                speed_mps: speed,
                duration_s: 30.0,
                mounting: Mounting::Random,
                out_of_plane: oop,
                noise: std::env::var_os("NOISE_OFF").is_none(),
                ..Default::default()
            };
            let opts = AlignOptions {
                hinge: std::env::var_os("HINGE").is_some(),
                ..Default::default()
            };
            let (rec, m) = sim(cfg);
            let a = estimate_alignment(&rec, &opts).unwrap();
            let mut line = format!("seed {seed} v {speed}:");
            for s in Segment::ALL {
                let i = s.index();
                let sa = a.per_segment[i].unwrap();
                let r = sa.rotation.matrix();
                let z_est: Vector3<f64> = r.row(2).transpose();
                let z_true: Vector3<f64> = m[i].row(2).transpose();
                let ax = z_est.dot(&z_true).clamp(-1.0, 1.0).acos().to_degrees();
                // Rate error of the aligned gyro z vs d(ref)/dt, estimated and true frame.
                let (mut e_est, mut e_true, mut nn) = (0.0, 0.0, 0.0);
                for k in 1..rec.len() - 1 {
                    let d = (rec[k + 1].reference.segment[i].unwrap()
                        - rec[k - 1].reference.segment[i].unwrap())
                        / (rec[k + 1].sample.t - rec[k - 1].sample.t);
                    let w = rec[k].sample.imu[i].gyr.unwrap();
                    e_est += (z_est.dot(&w) - d).powi(2);
                    e_true += (z_true.dot(&w) - d).powi(2);
                    nn += 1.0;
                }
                stats[i][2] = stats[i][2].max((e_est / nn).sqrt().to_degrees());
                stats[i][3] = stats[i][3].max((e_true / nn).sqrt().to_degrees());
                stats[i][0] = stats[i][0].max(ax);
                stats[i][1] += ax / 24.0;
                let e = r * m[i].transpose();
                let zero = e[(1, 0)].atan2(e[(0, 0)]).to_degrees();
                let mean_ref = rec
                    .iter()
                    .map(|x| x.reference.segment[i].unwrap())
                    .sum::<f64>()
                    / rec.len() as f64;
                line += &format!(
                    " {}: ax {ax:.2} zerr {:.2} pcadev {:.2} marg {:.2} |",
                    &s.name()[..2],
                    zero - mean_ref.to_degrees(),
                    sa.axis_vs_principal_rad.to_degrees(),
                    sa.sign_margin
                );
            }
            println!("{line}");
        }
    }
    println!(
        "axis error max/mean deg, max rate rms est/true deg/s: {:?}",
        stats.map(|s| s.map(|x| (x * 100.0).round() / 100.0))
    );
}
