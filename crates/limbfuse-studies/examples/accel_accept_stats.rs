//! Accelerometer acceptance statistics (issue 3, gating study):
//! `cargo run --release -p limbfuse-studies --example accel_accept_stats -- [FIRST] [LAST] [ideal]`
//!
//! For each speed and segment, the inclination error `theta_a - theta_true`
//! (deg) over the samples an acceptance test passes: mean, sd, share of
//! samples with |error| > 3 and > 5 deg and the part of the mean they
//! carry. Tests: the papers' `rho < zeta` (base); `rho < zeta` held for the
//! last T seconds (hold T); base plus `||omega|| < W` (gyro W rad/s). The
//! `mjls sel` row uses the segment MJLS would select (argmin rho, passing).
//! `ideal` as the third argument switches sensor errors off.

use clap::Parser;
use limbfuse_core::{Record, Segment};
use limbfuse_estimators::segment_kf::CommonParams;
use limbfuse_sim::{WalkingConfig, WalkingSimulator};
use limbfuse_studies::example_args::AccelAcceptStatsArgs;
use rayon::prelude::*;

#[derive(Clone, Copy, Default)]
struct Acc {
    n: f64,
    s: f64,
    s2: f64,
    n3: f64,
    s3: f64,
    n5: f64,
    s5: f64,
    total: f64,
}

impl Acc {
    fn push(&mut self, e: f64) {
        self.n += 1.0;
        self.s += e;
        self.s2 += e * e;
        if e.abs() > 3.0 {
            self.n3 += 1.0;
            self.s3 += e;
        }
        if e.abs() > 5.0 {
            self.n5 += 1.0;
            self.s5 += e;
        }
    }
    fn add(&mut self, o: &Acc) {
        self.n += o.n;
        self.s += o.s;
        self.s2 += o.s2;
        self.n3 += o.n3;
        self.s3 += o.s3;
        self.n5 += o.n5;
        self.s5 += o.s5;
        self.total += o.total;
    }
    fn row(&self) -> String {
        let m = self.s / self.n;
        let sd = (self.s2 / self.n - m * m).max(0.0).sqrt();
        format!(
            "{:.1} | {:+.2} | {:.2} | {:.1} | {:+.2} | {:.1} | {:+.2} | {:+.2}",
            100.0 * self.n / self.total,
            m,
            sd,
            100.0 * self.n3 / self.n,
            self.s3 / self.n,
            100.0 * self.n5 / self.n,
            self.s5 / self.n,
            (self.s - self.s3) / self.n,
        )
    }
}

const TESTS: [&str; 9] = [
    "base rho<zeta",
    "hold 10 ms",
    "hold 20 ms",
    "hold 50 ms",
    "hold 100 ms",
    "gyro 0.5 rad/s",
    "gyro 1.0 rad/s",
    "gyro 2.0 rad/s",
    "hold 50 ms + gyro 1.0",
];

fn wrapd(a: f64) -> f64 {
    libm::remainder(a, core::f64::consts::TAU).to_degrees()
}

fn main() {
    let args = AccelAcceptStatsArgs::parse();
    let (a, b, ideal) = (args.first, args.last, args.ideal.is_some());
    let zeta = CommonParams::default().zetas();
    println!("seeds {a}..={b}, ideal sensors: {ideal}");
    println!("| speed | segment | test | acc % | mean | sd | >3 % | mean from >3 | >5 % | mean from >5 | mean from <=3 |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for speed in [0.4, 1.0, 1.6] {
        // [test][segment 0..4, 4 = mjls selected]
        let per: Vec<Vec<[Acc; 5]>> = (a..=b)
            .into_par_iter()
            .map(|seed| {
                let cfg = WalkingConfig {
                    speed_mps: speed,
                    seed,
                    noise: !ideal,
                    ..WalkingConfig::default()
                };
                let records: Vec<Record> =
                    WalkingSimulator::new(cfg).expect("valid config").collect();
                let mut acc = vec![[Acc::default(); 5]; TESTS.len()];
                let mut run_start: [Option<f64>; 4] = [None; 4];
                for r in &records {
                    let t = r.sample.t;
                    let mut pass = [[false; 4]; 9];
                    let mut err = [0.0; 4];
                    let mut rho = [f64::INFINITY; 4];
                    for s in Segment::ALL {
                        let i = s.index();
                        let imu = &r.sample.imu[i];
                        let (Some(av), Some(truth)) = (imu.acc, r.reference.segment[i]) else {
                            run_start[i] = None;
                            continue;
                        };
                        let th = av.x.atan2(av.y);
                        err[i] = wrapd(th - truth);
                        rho[i] = (av.norm() - cfg.g).abs();
                        let base = rho[i] < zeta[i];
                        if base {
                            if run_start[i].is_none() {
                                run_start[i] = Some(t);
                            }
                        } else {
                            run_start[i] = None;
                        }
                        let held = |tt: f64| base && t - run_start[i].unwrap_or(t) >= tt - 1e-9;
                        let w = imu.gyr.map(|g| g.norm()).unwrap_or(f64::INFINITY);
                        pass[0][i] = base;
                        pass[1][i] = held(0.01);
                        pass[2][i] = held(0.02);
                        pass[3][i] = held(0.05);
                        pass[4][i] = held(0.1);
                        pass[5][i] = base && w < 0.5;
                        pass[6][i] = base && w < 1.0;
                        pass[7][i] = base && w < 2.0;
                        pass[8][i] = held(0.05) && w < 1.0;
                    }
                    for (k, p) in pass.iter().enumerate() {
                        for i in 0..4 {
                            acc[k][i].total += 1.0;
                            if p[i] {
                                acc[k][i].push(err[i]);
                            }
                        }
                        // MJLS: argmin rho among segments passing the test
                        let sel = (0..4)
                            .filter(|&i| p[i])
                            .min_by(|&x, &y| rho[x].total_cmp(&rho[y]));
                        acc[k][4].total += 1.0;
                        if let Some(i) = sel {
                            acc[k][4].push(err[i]);
                        }
                    }
                }
                acc
            })
            .collect();
        for (k, name) in TESTS.iter().enumerate() {
            for seg in 0..5 {
                let mut tot = Acc::default();
                for p in &per {
                    tot.add(&p[k][seg]);
                }
                let sname = if seg < 4 {
                    Segment::ALL[seg].name()
                } else {
                    "mjls sel"
                };
                println!("| {speed} | {sname} | {name} | {} |", tot.row());
            }
        }
    }
}
