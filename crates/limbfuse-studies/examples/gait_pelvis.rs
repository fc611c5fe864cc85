//! Paper 003 sec IV-B analogue on real data: the Vicon pelvis (PELV) of the
//! shared gaittoolbox trial as a CoM proxy, straight parts only,
//! position-only measurements (eqs 17-18), a 0.6-1.0 m/s library rescaled
//! to the pelvis height at mid-stance (sec IV-B).
//! `cargo run --release -p limbfuse-studies --example gait_pelvis -- [DATA_DIR] [--touchdown height|step-clock|mixed] [--continuous]`
//! (`--continuous`: the issue-19 configuration, bare and with the sway
//! restart the CLI applies (`SwayRestart`), median speed estimate over
//! the second half of each part).

use clap::Parser;
use limbfuse_core::{Estimator, Sample};
use limbfuse_estimators::imm_bslip::{
    ImmBslip, ImmBslipParams, ImmContinuous, ImmWeights, SwayRestart,
};
use limbfuse_models::bslip::BslipParams;
use limbfuse_sim::bslip::library::build_library;
use limbfuse_sim::bslip::search::SearchSettings;
use limbfuse_studies::example_args::GaitPelvisArgs;

fn main() {
    let args = GaitPelvisArgs::parse();
    let dir = args.data_dir;
    let path = std::path::Path::new(&dir).join("vicon-right.csv");
    let Ok(text) = std::fs::read_to_string(&path) else {
        eprintln!("skipped: {} not found", path.display());
        return;
    };
    let mut lines = text.lines().filter(|l| !l.starts_with("//"));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let idx = [col("PELV_1"), col("PELV_2"), col("PELV_3")];
    let p: Vec<[f64; 3]> = lines
        .map(|l| {
            let c: Vec<f64> = l
                .split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect();
            [c[idx[0]], c[idx[1]], c[idx[2]]]
        })
        .collect();
    let fs = 100.0;
    let n = p.len();
    // Smoothed horizontal velocity (central difference over +-10 samples).
    let half = 10;
    let vel: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(half), (k + half).min(n - 1));
            let dt = (b - a) as f64 / fs;
            [(p[b][0] - p[a][0]) / dt, (p[b][1] - p[a][1]) / dt]
        })
        .collect();
    // Straight parts: speed >= 0.7 m/s and heading within 20 deg of +-y (the walkway), >= 1.5 s.
    let straight: Vec<bool> = vel
        .iter()
        .map(|v| {
            let s = v[0].hypot(v[1]);
            s >= 0.7 && (v[0] / s).abs() < 20f64.to_radians().sin()
        })
        .collect();
    let mut runs = Vec::new();
    let mut k = 0;
    while k < n {
        if straight[k] {
            let s = k;
            while k < n && straight[k] && vel[k][1].signum() == vel[s][1].signum() {
                k += 1;
            }
            if (k - s) as f64 / fs >= 1.5 {
                runs.push((s, k));
            }
        } else {
            k += 1;
        }
    }
    let body = BslipParams::default();
    let speeds = [0.6, 0.7, 0.8, 0.9, 1.0];
    let lib = build_library(&body, &speeds, &SearchSettings::default(), |_, _| {}).unwrap();
    let base: Vec<_> = lib.iter().map(|g| g.template(&body)).collect();
    println!("straight parts (speed >= 0.7 m/s, heading within 20 deg of the walkway, >= 1.5 s): {runs:?} (samples at 100 Hz)");
    for (s, e) in runs {
        let dir_y = vel[s][1].signum();
        let fwd = [0.0, dir_y];
        let right = [dir_y, 0.0]; // fwd x up, up = +z
        let o = p[s];
        let local = |q: &[f64; 3]| {
            let d = [q[0] - o[0], q[1] - o[1]];
            [
                d[0] * fwd[0] + d[1] * fwd[1],
                q[2],
                d[0] * right[0] + d[1] * right[1],
            ]
        };
        let dist = local(&p[e - 1])[0];
        let measured = dist / ((e - 1 - s) as f64 / fs);
        // MS height: 90th percentile of the pelvis height over the part.
        let mut h: Vec<f64> = p[s..e].iter().map(|q| q[2]).collect();
        h.sort_by(f64::total_cmp);
        let h_ms = h[(0.9 * (h.len() - 1) as f64) as usize];
        for (label, templates) in [
            ("library as built (l0 = 1 m)", base.clone()),
            (
                "rescaled to the pelvis MS height",
                base.iter()
                    .map(|t| t.rescaled_to_height(h_ms).unwrap())
                    .collect::<Vec<_>>(),
            ),
        ] {
            // --touchdown step-clock|mixed: the touchdown rule (default height).
            let params = ImmBslipParams {
                touchdown: args.touchdown,
                ..ImmBslipParams::position_only()
            };
            if args.continuous {
                continuous(&templates, &p[s..e], &local, measured, label, (s, e));
                continue;
            }
            let mut imm = ImmBslip::new(&templates, params).unwrap();
            let mut hist = vec![0usize; templates.len()];
            let (mut wmean, mut nw, mut n2) = (0.0, 0, 0);
            for (i, q) in p[s..e].iter().enumerate() {
                let mut sample = Sample::empty(i as f64 / fs);
                let l = local(q);
                sample.com.pos = [Some(l[0]), Some(l[1]), Some(l[2])];
                let est = imm.step(&sample).unwrap();
                if i >= (e - s) / 2 {
                    let g = templates
                        .iter()
                        .position(|t| Some(t.speed) == est.speed)
                        .unwrap();
                    hist[g] += 1;
                    n2 += 1;
                    wmean += est.diag[3 * templates.len()].unwrap();
                    nw += 1;
                }
            }
            let mode = hist.iter().enumerate().max_by_key(|(_, c)| **c).unwrap().0;
            println!(
                "part {:.2}-{:.2} s, {label}: measured pelvis speed {measured:.3} m/s, MS height {h_ms:.3} m; second half: most likely gait {:.3} m/s for {:.0} % of samples, weight-averaged speed {:.3} m/s; most-likely histogram {:?} over speeds {:?}",
                s as f64 / fs,
                e as f64 / fs,
                templates[mode].speed,
                100.0 * hist[mode] as f64 / n2 as f64,
                wmean / nw as f64,
                hist,
                templates.iter().map(|t| (t.speed * 1000.0).round() / 1000.0).collect::<Vec<_>>()
            );
        }
    }
}

/// The continuous configuration on one straight part: median speed over
/// the second half.
fn continuous(
    templates: &[limbfuse_models::bslip::GaitTemplate],
    part: &[[f64; 3]],
    local: &dyn Fn(&[f64; 3]) -> [f64; 3],
    measured: f64,
    label: &str,
    (s, e): (usize, usize),
) {
    let fs = 100.0;
    let params = ImmBslipParams {
        weights: ImmWeights::Recursive,
        ..ImmBslipParams::position_only()
    };
    let bare = ImmContinuous::new(templates, params).unwrap();
    let runs: [(&str, Box<dyn Estimator>); 2] = [
        ("continuous", Box::new(bare.clone())),
        (
            "continuous, sway restart (as the CLI)",
            Box::new(SwayRestart::new(bare)),
        ),
    ];
    for (config, mut imm) in runs {
        let mut speeds = Vec::new();
        for (i, q) in part.iter().enumerate() {
            let mut sample = Sample::empty(i as f64 / fs);
            let l = local(q);
            sample.com.pos = [Some(l[0]), Some(l[1]), Some(l[2])];
            let est = imm.step(&sample).unwrap();
            if i >= part.len() / 2 {
                speeds.extend(est.speed);
            }
        }
        speeds.sort_by(f64::total_cmp);
        let median = speeds[speeds.len() / 2];
        let (mid, last) = (part.len() / 2, part.len() - 1);
        let second_half =
            (local(&part[last])[0] - local(&part[mid])[0]) / ((last - mid) as f64 / fs);
        println!(
            "part {:.2}-{:.2} s, {label}, {config}: measured pelvis speed {measured:.3} m/s (second half {second_half:.3}); second half: median speed estimate {median:.3} m/s (error {:+.3}; {:+.3} against the second half)",
            s as f64 / fs,
            e as f64 / fs,
            median - measured,
            median - second_half
        );
    }
}
