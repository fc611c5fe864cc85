//! `gait-events` final contacts (toe off) at other sample rates against the
//! motion-capture events of the shared gaitmap walk (docs/RESULTS.md, "Final
//! contacts at low sample rates"): the shape of the push-off trough around
//! the reference toe off, and per rate and anti-alias filter the toe off as
//! `gait-events` places it (corner or parabola, `gait_events::trough_time`),
//! as the parabola alone places it, and at the minimum of a band-limited
//! (windowed-sinc) interpolation of the samples, each against the 204.8 Hz
//! reference events and against the resampled reference. Each further
//! trial (no event reference needed) is resampled to the rates below its
//! own, and its toe offs there are compared with those at its own rate.
//! `cargo run --release -p limbfuse-studies --example final_contact_floor --
//! ../shared/data/gaitmap-foot-walk/trial.csv [OTHER_TRIAL ...]`

use std::path::Path;

use clap::Parser;
use limbfuse_core::{Estimator, Record, Side};
use limbfuse_estimators::gait_events::trough_time::{TroughModel, TroughSamples};
use limbfuse_estimators::gait_events::{FootSource, GaitDiag, GaitEvents, GaitEventsParams};
use limbfuse_io::TrialReader;
use limbfuse_signal::resample::{resample_trial, AntiAlias, ResampleOptions};
use limbfuse_studies::example_args::FinalContactFloorArgs;

/// One foot's signed sagittal rate and final contacts from `gait-events`.
struct FootRun {
    t: Vec<f64>,
    rate: Vec<Option<f64>>,
    final_contacts: Vec<f64>,
}

/// `gait-events` (defaults; the right foot is the trial's own leg) on `records`.
fn run(records: &[Record]) -> [FootRun; 2] {
    let mut e = GaitEvents::new(
        GaitEventsParams::default(),
        [Some(FootSource::OtherLeg), Some(FootSource::OwnLeg)],
    )
    .expect("two feet");
    let mut feet = [(); 2].map(|_| FootRun {
        t: vec![],
        rate: vec![],
        final_contacts: vec![],
    });
    for r in records {
        let est = e.step(&r.sample).expect("a step");
        for (foot, (rate, fc)) in feet.iter_mut().zip([
            (GaitDiag::RateLeft, GaitDiag::FcLeft),
            (GaitDiag::RateRight, GaitDiag::FcRight),
        ]) {
            foot.t.push(r.sample.t);
            foot.rate.push(est.diagnostic(rate));
            foot.final_contacts.extend(est.diagnostic(fc));
        }
    }
    feet
}

/// The 1 -> 0 steps of a side's contact reference.
fn reference_final_contacts(records: &[Record], side: usize) -> Vec<f64> {
    records
        .windows(2)
        .filter(|w| w[0].reference.contact[side] == Some(true))
        .filter(|w| w[1].reference.contact[side] == Some(false))
        .map(|w| w[1].sample.t)
        .collect()
}

/// Signed errors of `estimated` against the nearest of `reference` (within 0.25 s).
fn errors(estimated: &[f64], reference: &[f64]) -> Vec<f64> {
    reference
        .iter()
        .filter_map(|&r| {
            let e = estimated
                .iter()
                .map(|&x| x - r)
                .min_by(|a, b| a.abs().total_cmp(&b.abs()))?;
            (e.abs() < 0.25).then_some(e)
        })
        .collect()
}

/// "median / p95 (mean)" of |errors|, ms.
fn summary(e: &[f64]) -> String {
    let mut a: Vec<f64> = e.iter().map(|x| x.abs() * 1e3).collect();
    a.sort_by(f64::total_cmp);
    let q = |p: f64| {
        let x = p * (a.len() - 1) as f64;
        let (i, f) = (x.floor() as usize, x - x.floor());
        a[i] + f * (a[(i + 1).min(a.len() - 1)] - a[i])
    };
    let mean = e.iter().sum::<f64>() / e.len() as f64 * 1e3;
    format!("{:.1} / {:.1} ({:+.1})", q(0.5), q(0.95), mean)
}

/// The parabola's time, the minimum of the windowed-sinc interpolation and
/// whether `gait_events::trough_time` chose the corner, for the trough
/// whose lowest sample is near `fc`.
fn alternatives(foot: &FootRun, fc: f64) -> Option<(f64, f64, bool)> {
    let h = foot.t[1] - foot.t[0];
    let k0 = ((fc - foot.t[0]) / h).round() as usize;
    let w = |j: usize| foot.rate.get(j).copied().flatten();
    let k = (k0.checked_sub(2)?..=k0 + 2).min_by(|&a, &b| {
        w(a).unwrap_or(f64::MAX)
            .total_cmp(&w(b).unwrap_or(f64::MAX))
    })?;
    let (b2, b1, v, a1, a2) = (w(k - 2)?, w(k - 1)?, w(k)?, w(k + 1)?, w(k + 2)?);
    let den = b1 - 2.0 * v + a1;
    let parabola = foot.t[k] + (0.5 * (b1 - a1) / den).clamp(-0.5, 0.5) * h;
    let mut s = TroughSamples::new(
        foot.t[k],
        v,
        h,
        [Some((foot.t[k - 2], b2)), Some((foot.t[k - 1], b1))],
    );
    s.push_after(foot.t[k + 1], a1);
    s.push_after(foot.t[k + 2], a2);
    let corner = s.refined().1 == TroughModel::Corner;
    // Blackman-windowed sinc over +-8 samples, minimum on a 1/200-sample grid.
    let n = 8usize;
    let sinc = |u: f64| -> Option<f64> {
        let mut sum = 0.0;
        for j in k.checked_sub(n)?..=k + n {
            let x = u - (j as f64 - k as f64);
            if x.abs() >= n as f64 {
                continue;
            }
            let px = core::f64::consts::PI * x;
            let kernel = if x == 0.0 { 1.0 } else { px.sin() / px };
            let c = core::f64::consts::PI * x / n as f64;
            sum += w(j)? * kernel * (0.42 + 0.5 * c.cos() + 0.08 * (2.0 * c).cos());
        }
        Some(sum)
    };
    let mut best = (f64::MAX, 0.0);
    for i in -200..=200 {
        let u = i as f64 / 200.0;
        let value = sinc(u)?;
        if value < best.0 {
            best = (value, u);
        }
    }
    Some((parabola, foot.t[k] + best.1 * h, corner))
}

fn read(path: &Path) -> Vec<Record> {
    let mut r =
        TrialReader::open(path).unwrap_or_else(|e| panic!("{e} (run from the repository root)"));
    let mut out = vec![];
    while let Some(rec) = r.next_record().expect("a record") {
        out.push(rec);
    }
    out
}

/// Resampled to `rate` (default filter), or as recorded for 0.
fn at_rate(path: &Path, native: &[Record], rate: f64, anti_alias: AntiAlias) -> Vec<Record> {
    if rate == 0.0 {
        return native.to_vec();
    }
    let reader = TrialReader::open(path).expect("the trial");
    resample_trial(
        reader,
        &ResampleOptions {
            rate_hz: rate,
            anti_alias,
        },
    )
    .expect("resampled")
    .records
}

/// Toe offs of `path` at lower rates against those at its own rate.
fn rate_shift(path: &Path) {
    let native = read(path);
    let own_rate = 1.0 / (native[1].sample.t - native[0].sample.t);
    let base = run(&native);
    // Per foot: (gait-events toe off, parabola's, corner chosen).
    let own: Vec<Vec<(f64, f64, bool)>> = base
        .iter()
        .map(|f| {
            f.final_contacts
                .iter()
                .filter_map(|&fc| alternatives(f, fc).map(|a| (fc, a.0, a.2)))
                .collect()
        })
        .collect();
    let base_parabola: Vec<Vec<f64>> = own
        .iter()
        .map(|v| v.iter().map(|a| a.1).collect())
        .collect();
    let own_n: usize = own.iter().map(Vec::len).sum();
    let own_corners = own.iter().flatten().filter(|a| a.2).count();
    let largest_move = own
        .iter()
        .flatten()
        .map(|a| (a.0 - a.1).abs())
        .fold(0.0f64, f64::max);
    println!(
        "\n{} ({own_rate:.1} Hz, {own_n} toe offs, {own_corners} corners, at most {:.2} ms from the parabola's): toe offs at a lower rate minus at {own_rate:.1} Hz, median / p95 (mean) ms",
        path.display(),
        largest_move * 1e3
    );
    for rate in [200.0, 100.0, 60.0, 50.0] {
        if rate >= own_rate - 1e-6 {
            continue;
        }
        let feet = run(&at_rate(path, &native, rate, AntiAlias::WindowedSinc));
        let (mut shift, mut parabola_shift, mut n, mut corners) = (vec![], vec![], 0, 0);
        for side in 0..2 {
            let foot = &feet[side];
            shift.extend(errors(&foot.final_contacts, &base[side].final_contacts));
            let mut p = vec![];
            for &fc in &foot.final_contacts {
                if let Some((tp, _, corner)) = alternatives(foot, fc) {
                    p.push(tp);
                    n += 1;
                    corners += usize::from(corner);
                }
            }
            parabola_shift.extend(errors(&p, &base_parabola[side]));
        }
        if shift.is_empty() {
            println!("  {rate} Hz: no toe off");
            continue;
        }
        println!(
            "  {rate} Hz: {n} toe offs ({corners} corners): gait-events {}, parabola alone {}",
            summary(&shift),
            summary(&parabola_shift)
        );
    }
}

fn main() {
    let args = FinalContactFloorArgs::parse();
    let path = Path::new(&args.trial);
    let native = read(path);
    let native_fc = [0, 1].map(|s| reference_final_contacts(&native, s));
    let feet = run(&native);
    // The trough's mean shape (left foot) around the reference toe off.
    let left = &feet[Side::Left.index()];
    let h = left.t[1] - left.t[0];
    let mut profile = vec![(0.0, 0usize); 41];
    for &r in &native_fc[Side::Left.index()] {
        let k = ((r - left.t[0]) / h).round() as usize;
        if k < 20 || k + 20 >= left.t.len() {
            continue;
        }
        for (i, p) in profile.iter_mut().enumerate() {
            if let Some(w) = left.rate[k + i - 20] {
                p.0 += w;
                p.1 += 1;
            }
        }
    }
    println!(
        "push-off trough, left foot, mean rate (rad/s) around its {} reference toe offs:",
        profile[20].1
    );
    for (i, p) in profile.iter().enumerate() {
        println!(
            "  {:+6.1} ms  {:6.2}",
            (i as f64 - 20.0) * h * 1e3,
            p.0 / p.1.max(1) as f64
        );
    }
    println!(
        "\nrate, filter | toe offs (corner chosen) | gait-events vs 204.8 Hz ref | vs resampled ref | parabola vs 204.8 Hz ref | sinc minimum vs 204.8 Hz ref | resampled ref - 204.8 Hz ref (mean, max)"
    );
    let cases: [(f64, AntiAlias); 11] = [
        (0.0, AntiAlias::WindowedSinc),
        (200.0, AntiAlias::WindowedSinc),
        (128.0, AntiAlias::WindowedSinc),
        (102.4, AntiAlias::WindowedSinc),
        (100.0, AntiAlias::WindowedSinc),
        (60.0, AntiAlias::WindowedSinc),
        (50.0, AntiAlias::WindowedSinc),
        (60.0, AntiAlias::None),
        (50.0, AntiAlias::None),
        (60.0, AntiAlias::Boxcar),
        (50.0, AntiAlias::Boxcar),
    ];
    for (rate, anti_alias) in cases {
        let records = at_rate(path, &native, rate, anti_alias);
        let feet = run(&records);
        let (mut own, mut at_native, mut parabola, mut sinc, mut shift) =
            (vec![], vec![], vec![], vec![], vec![]);
        let (mut n, mut corners) = (0, 0);
        for side in 0..2 {
            let foot = &feet[side];
            let own_fc = reference_final_contacts(&records, side);
            own.extend(errors(&foot.final_contacts, &own_fc));
            at_native.extend(errors(&foot.final_contacts, &native_fc[side]));
            shift.extend(errors(&own_fc, &native_fc[side]));
            let (mut p, mut s) = (vec![], vec![]);
            for &fc in &foot.final_contacts {
                if let Some((tp, ts, corner)) = alternatives(foot, fc) {
                    p.push(tp);
                    s.push(ts);
                    n += 1;
                    corners += usize::from(corner);
                }
            }
            parabola.extend(errors(&p, &native_fc[side]));
            sinc.extend(errors(&s, &native_fc[side]));
        }
        let label = if rate == 0.0 {
            "204.8 Hz".to_string()
        } else {
            format!("{rate} Hz")
        };
        let max_shift = shift.iter().fold(0.0f64, |m, x| m.max(x.abs())) * 1e3;
        println!(
            "{label}, {} | {n} ({corners}) | {} | {} | {} | {} | {:+.1}, {:.1} ms",
            anti_alias.label(),
            summary(&at_native),
            summary(&own),
            summary(&parabola),
            summary(&sinc),
            shift.iter().sum::<f64>() / shift.len() as f64 * 1e3,
            max_shift
        );
    }
    for other in &args.others {
        rate_shift(Path::new(other));
    }
}
