//! Resampling against analytic signals: a sine below the output Nyquist
//! frequency keeps its amplitude and phase, one above it is attenuated (not
//! aliased into the band), a constant stays exact, gaps stay missing.
//!
//! `cargo test -p limbfuse-signal --test integration -- resample::response_table --nocapture`
//! prints the measured response quoted in docs/TUNING.md.

use std::f64::consts::PI;
use std::path::Path;

use limbfuse_core::Record;
use limbfuse_io::{TrialLayout, TrialMeta, TrialReader, TrialWriter};
use limbfuse_signal::resample::{
    resample_series, resample_trial, uniform_grid, AntiAlias, ChannelMethod, ResampleOptions,
    Series,
};
use nalgebra::Vector3;

fn sine(rate_in: f64, duration: f64, f: f64, phase: f64) -> Series {
    let n = (duration * rate_in) as usize + 1;
    let t: Vec<f64> = (0..n).map(|k| k as f64 / rate_in).collect();
    let v = t
        .iter()
        .map(|&t| (2.0 * PI * f * t + phase).sin())
        .collect();
    Series { t, v }
}

/// Amplitude and phase (rad) of the component at `f` in the output samples
/// at least `margin` seconds from both ends (least-squares fit of a sin and
/// a cos), relative to the input sine.
fn gain_phase(grid: &[f64], out: &[Option<f64>], f: f64, phase: f64, margin: f64) -> (f64, f64) {
    let (t0, t1) = (grid[0] + margin, grid[grid.len() - 1] - margin);
    let (mut ss, mut cc, mut sc, mut ys, mut yc) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (t, y) in grid.iter().zip(out) {
        if *t < t0 || *t > t1 {
            continue;
        }
        let y = y.expect("present inside the trial");
        let (s, c) = (2.0 * PI * f * t + phase).sin_cos();
        ss += s * s;
        cc += c * c;
        sc += s * c;
        ys += y * s;
        yc += y * c;
    }
    // Solve [ss sc; sc cc] [a; b] = [ys; yc]: y ~ a sin + b cos.
    let det = ss * cc - sc * sc;
    let a = (ys * cc - yc * sc) / det;
    let b = (yc * ss - ys * sc) / det;
    ((a * a + b * b).sqrt(), b.atan2(a))
}

/// RMS of the output inside the margins relative to the input RMS (1/sqrt 2).
fn rms_ratio(grid: &[f64], out: &[Option<f64>], margin: f64) -> f64 {
    let (t0, t1) = (grid[0] + margin, grid[grid.len() - 1] - margin);
    let v: Vec<f64> = grid
        .iter()
        .zip(out)
        .filter(|(t, _)| **t >= t0 && **t <= t1)
        .map(|(_, y)| y.unwrap())
        .collect();
    (v.iter().map(|y| y * y).sum::<f64>() / v.len() as f64).sqrt() * 2f64.sqrt()
}

fn run(
    rate_in: f64,
    rate_out: f64,
    f: f64,
    phase: f64,
    m: ChannelMethod,
) -> (Vec<f64>, Vec<Option<f64>>) {
    let s = sine(rate_in, 10.0, f, phase);
    let grid = uniform_grid(0.0, 10.0, rate_out).unwrap();
    let out = resample_series(&s, &grid, rate_out, m);
    (grid, out)
}

const SINC: ChannelMethod = ChannelMethod::Decimate(AntiAlias::WindowedSinc);

#[test]
fn sine_in_the_pass_band_keeps_amplitude_and_phase() {
    // 200 Hz and 100 Hz to 50 Hz, 0.5-10 Hz (gait content): |gain - 1| <
    // 1e-3, |phase| < 1e-3 rad (the kernel is symmetric: no delay).
    for rate_in in [100.0, 200.0, 1000.0] {
        for f in [0.5, 1.0, 2.0, 5.0, 10.0] {
            let (grid, out) = run(rate_in, 50.0, f, 0.3, SINC);
            let (g, p) = gain_phase(&grid, &out, f, 0.3, 0.25);
            assert!((g - 1.0).abs() < 1e-3, "{rate_in} Hz, {f} Hz: gain {g}");
            assert!(p.abs() < 1e-3, "{rate_in} Hz, {f} Hz: phase {p}");
        }
    }
}

#[test]
fn sine_above_the_output_nyquist_is_removed_not_aliased() {
    // 40 Hz sampled at 200 Hz would alias to 10 Hz at 50 Hz: after the
    // filter less than 1e-3 of it remains. Without anti-aliasing it passes whole.
    let (grid, out) = run(200.0, 50.0, 40.0, 0.1, SINC);
    let r = rms_ratio(&grid, &out, 0.25);
    assert!(r < 1e-3, "windowed sinc leaves {r} of a 40 Hz sine");
    let (grid, out) = run(
        200.0,
        50.0,
        40.0,
        0.1,
        ChannelMethod::Decimate(AntiAlias::None),
    );
    assert!(rms_ratio(&grid, &out, 0.25) > 0.9);
    // The boxcar (mean over one output period) only halves it.
    let (grid, out) = run(
        200.0,
        50.0,
        40.0,
        0.1,
        ChannelMethod::Decimate(AntiAlias::Boxcar),
    );
    let b = rms_ratio(&grid, &out, 0.25);
    assert!(b > 0.05 && b < 0.5, "boxcar {b}");
}

#[test]
fn boxcar_and_linear_keep_low_frequencies_within_stated_bounds() {
    // Boxcar over one 50 Hz period has gain sinc(f / 50): 0.9836 at 5 Hz, no phase.
    let (grid, out) = run(
        200.0,
        50.0,
        5.0,
        0.2,
        ChannelMethod::Decimate(AntiAlias::Boxcar),
    );
    let (g, p) = gain_phase(&grid, &out, 5.0, 0.2, 0.25);
    assert!((g - 0.9836).abs() < 2e-3 && p.abs() < 1e-3, "{g} {p}");
    // Linear interpolation of a 1 kHz channel (encoders): point sampling.
    let (grid, out) = run(1000.0, 50.0, 5.0, 0.2, ChannelMethod::Linear);
    let (g, p) = gain_phase(&grid, &out, 5.0, 0.2, 0.0);
    assert!((g - 1.0).abs() < 1e-9 && p.abs() < 1e-9, "{g} {p}");
    // Upsampling 50 Hz to 200 Hz is linear interpolation: exact at the
    // input instants, cos(pi f / 50) = 0.992 half-way between them at 2 Hz;
    // the fitted gain is 0.995, no phase.
    let (grid, out) = run(50.0, 200.0, 2.0, 0.2, SINC);
    let (g, p) = gain_phase(&grid, &out, 2.0, 0.2, 0.0);
    assert!((g - 0.995).abs() < 1e-3 && p.abs() < 1e-3, "{g} {p}");
}

#[test]
fn constant_stays_exact_with_gaps_and_irregular_spacing() {
    let mut s = Series::default();
    let mut t: f64 = 0.0;
    let mut k = 0u64;
    while t < 10.0 {
        // jittered 200 Hz with a 0.5 s dropout at 4 s and a lone sample at 4.2 s
        if !(4.0..4.5).contains(&t) || (t - 4.2).abs() < 0.003 {
            s.t.push(t);
            s.v.push(-3.25);
        }
        k += 1;
        t = k as f64 * 0.005 + 0.001 * ((k * 7919) % 13) as f64 / 13.0;
    }
    let grid = uniform_grid(0.0, *s.t.last().unwrap(), 50.0).unwrap();
    for m in [
        SINC,
        ChannelMethod::Decimate(AntiAlias::Boxcar),
        ChannelMethod::Linear,
    ] {
        let out = resample_series(&s, &grid, 50.0, m);
        for (tg, y) in grid.iter().zip(&out) {
            match y {
                Some(y) => assert!((y + 3.25).abs() < 1e-12, "{m:?} at {tg}: {y}"),
                None => assert!(
                    (4.0..4.5).contains(tg),
                    "{m:?}: missing at {tg} outside the gap"
                ),
            }
        }
        // Deep inside the gap (no sample within the output period): missing.
        let k = grid.iter().position(|&t| (t - 4.4).abs() < 1e-9).unwrap();
        assert_eq!(out[k], None, "{m:?}");
    }
}

#[test]
fn ramp_is_exact_with_the_symmetric_kernel() {
    // A linear function is reproduced by any symmetric normalised kernel on
    // a grid symmetric about the output time.
    let s = Series {
        t: (0..2001).map(|k| k as f64 / 200.0).collect(),
        v: (0..2001).map(|k| 0.3 * k as f64 / 200.0 - 1.0).collect(),
    };
    let grid = uniform_grid(0.0, 10.0, 50.0).unwrap();
    let out = resample_series(&s, &grid, 50.0, SINC);
    for (t, y) in grid.iter().zip(&out) {
        let e = (y.unwrap() - (0.3 * t - 1.0)).abs();
        if *t >= 0.2 && *t <= 9.8 {
            assert!(e < 1e-12, "{t}: {e}");
        } else {
            // Within W = 0.2 s of the ends: one-sided mean over an output
            // period, off by at most a quarter period of slope.
            assert!(e <= 0.3 * 0.005 + 1e-12, "{t}: {e}");
        }
    }
}

fn write(records: &[Record], layout: TrialLayout, path: &Path) {
    let mut meta = TrialMeta::trial_v1();
    meta.set("sample_rate_hz", 1000);
    let f = std::fs::File::create(path).unwrap();
    let mut w = TrialWriter::new(f, &meta, layout).unwrap();
    for r in records {
        w.write(r).unwrap();
    }
    w.finish().unwrap();
}

#[test]
fn mixed_rate_trial_with_a_dropout_resamples_to_50_hz() {
    // 1 kHz rows: encoder every row, IMU every 10th row (100 Hz) except a
    // 1 s dropout, reference every 10th row.
    let layout = TrialLayout {
        acc: [false, true, false, false],
        gyr: [false, true, false, false],
        quat: [false, true, false, false],
        encoder: [false, true, false],
        segment_ref: [false, true, false, false],
        phase_ref: true,
        ..Default::default()
    };
    let recs: Vec<Record> = (0..=5000)
        .map(|k| {
            let t = k as f64 / 1000.0;
            let mut r = Record::default();
            r.sample.t = t;
            r.sample.encoder[1] = Some((2.0 * PI * t).sin());
            if k % 10 == 0 {
                let th = 0.5 * (2.0 * PI * t).sin();
                r.reference.segment[1] = Some(th);
                r.reference.phase = Some(if t < 2.5 {
                    limbfuse_core::GaitPhase::Ss1
                } else {
                    limbfuse_core::GaitPhase::Ds
                });
                if !(2.0..3.0).contains(&t) {
                    r.sample.imu[1].acc = Some(Vector3::new(9.81 * th.sin(), 9.81 * th.cos(), 0.0));
                    r.sample.imu[1].gyr = Some(Vector3::new(0.0, 0.0, 1.0));
                    let h = 0.5 * th;
                    r.sample.imu[1].quat = Some([h.cos(), 0.0, 0.0, h.sin()]);
                }
            }
            r
        })
        .collect();
    let d = tempfile::tempdir().unwrap();
    let path = d.path().join("mixed.csv");
    write(&recs, layout, &path);
    let out = resample_trial(
        TrialReader::open(&path).unwrap(),
        &ResampleOptions::new(50.0),
    )
    .unwrap();
    assert_eq!(out.records.len(), 251);
    assert_eq!(out.layout, layout);
    assert_eq!(out.meta.get("sample_rate_hz"), Some("50"));
    for r in &out.records {
        let t = r.sample.t;
        let enc = r.sample.encoder[1].unwrap();
        assert!((enc - (2.0 * PI * t).sin()).abs() < 1e-12, "{t}");
        let rf = r.reference.segment[1].unwrap();
        // 100 Hz reference linearly interpolated (exact at the 50 Hz instants).
        assert!((rf - 0.5 * (2.0 * PI * t).sin()).abs() < 1e-12, "{t}");
        let imu = &r.sample.imu[1];
        // IMU missing inside the dropout (2.00-2.99 s, no sample within +-10 ms).
        if t > 2.0 + 1e-9 && t < 2.99 - 1e-9 {
            assert!(
                imu.acc.is_none() && imu.gyr.is_none() && imu.quat.is_none(),
                "{t}"
            );
        } else {
            assert!(imu.gyr.is_some() && imu.quat.is_some(), "{t}");
            assert!((imu.gyr.unwrap().z - 1.0).abs() < 1e-12);
            let q = imu.quat.unwrap();
            assert!((q.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-12);
        }
        assert!(r.reference.phase.is_some());
    }
    // Write and read back: a valid trial file.
    let back = d.path().join("back.csv");
    limbfuse_signal::resample::resample_file(&path, &back, &ResampleOptions::new(50.0)).unwrap();
    let n = TrialReader::open(&back).unwrap().count();
    assert_eq!(n, 251);
}

#[test]
fn bad_rate_is_an_error() {
    let d = tempfile::tempdir().unwrap();
    let path = d.path().join("t.csv");
    std::fs::write(&path, "t,hip_enc\n0,0\n0.1,1\n").unwrap();
    for rate in [0.0, -5.0, f64::NAN, f64::INFINITY, 1e9] {
        let e = resample_trial(
            TrialReader::open(&path).unwrap(),
            &ResampleOptions::new(rate),
        );
        assert!(e.unwrap_err().to_string().contains("rate"));
    }
}

#[test]
fn response_table() {
    // Measured response (printed with --nocapture; quoted in docs/TUNING.md).
    println!("rate_in  f_Hz  sinc_gain  sinc_phase_rad  boxcar_gain");
    for rate_in in [100.0, 200.0] {
        for f in [1.0, 5.0, 10.0, 12.5, 15.0, 17.5, 20.0, 22.5, 30.0, 40.0] {
            let (grid, s) = run(rate_in, 50.0, f, 0.3, SINC);
            let (_, b) = run(
                rate_in,
                50.0,
                f,
                0.3,
                ChannelMethod::Decimate(AntiAlias::Boxcar),
            );
            if f < 25.0 {
                let (g, p) = gain_phase(&grid, &s, f, 0.3, 0.25);
                let (gb, _) = gain_phase(&grid, &b, f, 0.3, 0.25);
                println!("{rate_in:>7} {f:>5} {g:>10.6} {p:>15.2e} {gb:>12.4}");
            } else if f < rate_in / 2.0 {
                println!(
                    "{rate_in:>7} {f:>5} {:>10.2e} {:>15} {:>12.4}",
                    rms_ratio(&grid, &s, 0.25),
                    "(aliased)",
                    rms_ratio(&grid, &b, 0.25)
                );
            }
        }
    }
}

/// An audit added 1e6 s to `t` from row 251 on: `resample --rate 50` went
/// on to allocate ~103 GB (50 million records of ~2 KB) and was aborted by
/// the allocator. Now refused before anything is allocated, with the
/// file, the rate, the size in memory and the limit.
#[test]
fn a_jump_in_t_is_refused_before_allocating_with_the_memory_it_would_take() {
    let d = tempfile::tempdir().unwrap();
    let path = d.path().join("jump.csv");
    std::fs::write(&path, "t,hip_enc\n0,0\n0.1,1\n1000000,2\n").unwrap();
    let e = resample_trial(
        TrialReader::open(&path).unwrap(),
        &ResampleOptions::new(50.0),
    )
    .unwrap_err()
    .to_string();
    for needle in [
        "jump.csv",
        "--rate 50 Hz",
        "50000001 output samples",
        "GB in memory",
        "limit of 10 GiB",
    ] {
        assert!(e.contains(needle), "`{needle}` in: {e}");
    }
    // The largest legitimate resample, an hour at 1 kHz, stays within it.
    let hour = 3600.0 * 1000.0 + 1.0;
    assert!(
        hour * limbfuse_signal::resample::bytes_per_output_sample() as f64
            <= limbfuse_signal::resample::MAX_RESAMPLE_BYTES as f64
    );
}
