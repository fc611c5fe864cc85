//! The sensor gate as it was before its fast path (every IMU visited, every
//! check of a complete gyroscope vector made in turn on copies), kept to
//! test that [`SampleGate::check`] screens, counts and remembers exactly as
//! it did. The checks after the complete gyroscope vector's, which have no
//! fast path, are the gate's own ([`SampleGate::check_imu_rest`]).

use super::*;
use nalgebra::Vector3;

/// [`SampleGate::check`] before the fast path, on `gate`'s own state.
fn reference_check(gate: &mut SampleGate, sample: &Sample) -> Screening {
    let mut out = Screening::default();
    let before = gate.rejections.total();
    let r = gate.ranges;
    let lim = gate.limits;
    let t = sample.t;
    let within = |v: &Vector3<f64>, limit: f64| v.iter().all(|x| x.abs() <= limit);
    let clipped = |v: &Vector3<f64>, fs: Option<f64>| {
        fs.is_some_and(|fs| v.iter().any(|x| x.abs() >= CLIPPED_FRACTION * fs))
    };
    let dt = gate.last_t.map_or(f64::NAN, |t0| t - t0);
    gate.last_t = Some(t);
    let imus = sample.imu.iter().chain(sample.other_leg_imu.iter());
    for (k, imu) in imus.enumerate() {
        let (rej, track) = (&mut gate.rejections, &mut gate.tracks[k]);
        let bit = 1u8 << k;
        let alpha = lim.angular_accel_rad_s2[k % 4];
        let mut gyro_stuck = false;
        let mut gyr = imu.gyr;
        if let Some(g) = imu.gyr {
            if !within(&g, r.gyro_rad_s) {
                gyr = None;
                rej.gyro += 1;
            } else if clipped(&g, r.gyro_full_scale_rad_s) {
                gyr = None;
                rej.gyro += 1;
                rej.clipped += 1;
            } else if let Some(why) = track[0].check(&g, t, Some(alpha), &lim) {
                gyr = None;
                rej.gyro += 1;
                gyro_stuck = why == Implausible::Stuck;
                tally(rej, why);
            }
            if gyr.is_none() {
                out.gyr |= bit;
            }
        }
        // (the incomplete vectors and the accelerometer: no fast path there)
        gate.check_imu_rest(k, imu, gyr.as_ref(), gyro_stuck, (t, dt), &mut out);
    }
    let rej = &mut gate.rejections;
    for (j, e) in sample.encoder.iter().enumerate() {
        if e.is_some_and(|x| !x.is_finite() || x.abs() > r.encoder_rad) {
            out.encoder |= 1 << j;
            rej.encoder += 1;
        }
    }
    if gate.rejections.total() > before && gate.rejections.first_t.is_none() {
        gate.rejections.first_t = Some(sample.t);
    }
    out
}

/// A deterministic stream of pseudo-random numbers in [0, 1).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn pick<T: Copy>(&mut self, from: &[T]) -> T {
        from[(self.next() * from.len() as f64) as usize % from.len()]
    }
}

/// A reading of `scale`, now and then replaced by a value at or next to a
/// threshold of `ranges` (range, clipping, beyond), a glitch or a jump.
fn cell(rng: &mut Lcg, base: f64, scale: f64, ranges: &SensorRanges, gyro: bool) -> f64 {
    if rng.next() > 0.03 {
        return base + scale * (rng.next() - 0.5);
    }
    let range = if gyro {
        ranges.gyro_rad_s
    } else {
        ranges.acc_m_s2
    };
    let clip = if gyro {
        ranges
            .gyro_full_scale_rad_s
            .map_or(range, |fs| CLIPPED_FRACTION * fs)
    } else {
        ranges
            .acc_full_scale_m_s2
            .map_or(range, |fs| ACC_CLIPPED_FRACTION * fs)
    };
    let below = |x: f64| f64::from_bits(x.to_bits() - 1);
    let above = |x: f64| f64::from_bits(x.to_bits() + 1);
    let v = rng.pick(&[
        range,
        below(range),
        above(range),
        clip,
        below(clip),
        above(clip),
        f64::NAN,
        f64::INFINITY,
        1e300,
        base + 30.0,
        base + 120.0,
        0.0,
    ]);
    if rng.next() < 0.5 {
        -v
    } else {
        v
    }
}

/// A sample of both legs' IMUs with glitches, threshold values, repeats
/// (stuck runs), missing and incomplete vectors, after `prev`.
fn next_sample(rng: &mut Lcg, prev: &Sample, ranges: &SensorRanges) -> Sample {
    let mut s = *prev;
    s.t = prev.t + rng.pick(&[0.01, 0.01, 0.01, 0.02, 0.005]);
    let imus = s.imu.iter_mut().chain(s.other_leg_imu.iter_mut());
    for (k, imu) in imus.enumerate() {
        let keep = rng.next();
        if keep < 0.6 && k != 7 {
            // a new reading (IMU 7 keeps repeating: a stuck sensor)
            let g: [f64; 3] = core::array::from_fn(|_| cell(rng, 1.0, 6.0, ranges, true));
            let a: [f64; 3] = core::array::from_fn(|j| {
                let base = if j == 1 { 9.81 } else { 0.0 };
                cell(rng, base, 8.0, ranges, false)
            });
            imu.gyr = Some(Vector3::from(g));
            imu.acc = Some(Vector3::from(a));
            imu.gyr_partial = [None; 3];
            imu.acc_partial = [None; 3];
        }
        if rng.next() < 0.05 {
            let g = imu.gyr.map_or([Some(0.5); 3], |v| v.map(Some).into());
            imu.gyr = None;
            imu.gyr_partial = core::array::from_fn(|j| g[j].filter(|_| rng.next() < 0.6));
        }
        if rng.next() < 0.05 {
            let a = imu.acc.map_or([Some(9.0); 3], |v| v.map(Some).into());
            imu.acc = None;
            imu.acc_partial = core::array::from_fn(|j| a[j].filter(|_| rng.next() < 0.6));
        }
        if rng.next() < 0.02 {
            *imu = ImuSample::default();
        }
    }
    for e in s.encoder.iter_mut() {
        *e = Some(rng.pick(&[0.3, -1.2, 3.5, f64::NAN, 1e300])).filter(|_| rng.next() > 0.1);
    }
    s
}

/// [`SampleGate::check`] and the reference agree sample by sample on
/// which readings to drop, on the counts and on the whole remembered
/// state, for streams full of glitches, values at and next to every
/// threshold, stuck runs and incomplete vectors, with the default ranges,
/// without a full scale, and with a full scale above the range.
#[test]
fn issue_18_the_gate_fast_path_screens_as_every_check_does() {
    let tight = SensorRanges {
        gyro_rad_s: 10.0,
        acc_m_s2: 50.0,
        encoder_rad: 1.0,
        gyro_full_scale_rad_s: Some(12.0),
        acc_full_scale_m_s2: Some(55.0),
    };
    let no_fs = SensorRanges {
        gyro_full_scale_rad_s: None,
        acc_full_scale_m_s2: None,
        ..SensorRanges::default()
    };
    for (seed, ranges) in [(1, SensorRanges::default()), (2, no_fs), (3, tight)] {
        let mut rng = Lcg(seed);
        let (mut fast, mut slow) = (SampleGate::new(ranges), SampleGate::new(ranges));
        let mut s = Sample::empty(0.0);
        let mut rejected = 0;
        for k in 0..20_000 {
            s = next_sample(&mut rng, &s, &ranges);
            let (a, b) = (fast.check(&s), reference_check(&mut slow, &s));
            assert_eq!(a, b, "seed {seed}, sample {k}");
            assert_eq!(format!("{fast:?}"), format!("{slow:?}"), "sample {k}");
            rejected += u32::from(!a.is_clean());
        }
        let r = fast.rejections();
        assert!(rejected > 1000 && r.jumps > 0 && r.stuck > 0, "{r:?}");
        // (with the tight ranges the range check catches every clipped value first)
        assert_eq!(r.clipped > 0, seed == 1, "{r:?}");
    }
}
