//! [`estimate_alignment`]: axis, sign and in-plane zero of every sensor.

use std::f64::consts::PI;

use limbfuse_core::{Record, Segment};
use nalgebra::{Rotation3, Vector3};

use super::axis::principal_axis;
use super::gait_window::walking_mask;
use super::leg_side::detect_leg;
use super::legs::{leg_axes, LegAxes};
use super::series::{acc, gyr, quiet_window, turning_mask};
use super::trunk::trunk_axis;
use super::zero::{angle_series, provisional, rot_z, static_angle};
use super::{AlignError, AlignOptions, Alignment, AxisMethod, SensorAlignment, ZeroMethod};

use super::legs::LEG;

fn check_options(o: &AlignOptions) -> Result<(), AlignError> {
    let checks: [(&'static str, f64, f64, f64, &'static str); 18] = [
        (
            "quiet_gyro_max",
            o.quiet_gyro_max,
            0.0,
            10.0,
            "(0, 10] rad/s",
        ),
        ("quiet_acc_dev", o.quiet_acc_dev, 0.0, 20.0, "(0, 20] m/s^2"),
        ("quiet_min_s", o.quiet_min_s, 0.0, 1e6, "(0, 1e6] s"),
        (
            "max_standing_offset_rad",
            o.max_standing_offset_rad,
            0.0,
            PI,
            "(0, pi] rad",
        ),
        (
            "min_gyro_rms",
            o.min_gyro_rms,
            -1e-300,
            100.0,
            "[0, 100] rad/s",
        ),
        (
            "max_hinge_deviation_rad",
            o.max_hinge_deviation_rad,
            0.0,
            PI,
            "(0, pi] rad",
        ),
        (
            "turn_max_rate",
            o.turn_max_rate,
            0.0,
            100.0,
            "(0, 100] rad/s",
        ),
        ("turn_window_s", o.turn_window_s, 0.0, 100.0, "(0, 100] s"),
        ("up_tau_s", o.up_tau_s, 0.0, 1e3, "(0, 1000] s"),
        (
            "gyro_axis_max_tilt_rad",
            o.gyro_axis_max_tilt_rad,
            -1e-300,
            0.5,
            "[0, 0.5] rad",
        ),
        ("zero_window_s", o.zero_window_s, 0.0, 1e6, "(0, 1e6] s"),
        ("trunk_min_corr", o.trunk_min_corr, -1e-300, 1.0, "[0, 1]"),
        ("walk_window_s", o.walk_window_s, 0.0, 1e3, "(0, 1000] s"),
        (
            "walk_min_autocorr",
            o.walk_min_autocorr,
            -1.0,
            1.0,
            "(-1, 1]",
        ),
        ("min_walking_s", o.min_walking_s, -1e-300, 1e6, "[0, 1e6] s"),
        ("max_axis_ratio", o.max_axis_ratio, 0.0, 1.0, "(0, 1]"),
        (
            "min_sign_margin",
            o.min_sign_margin,
            -1e-300,
            10.0,
            "[0, 10]",
        ),
        ("leg_min_score", o.leg_min_score, 0.0, 2.0, "(0, 2]"),
    ];
    for (name, value, lo, hi, range) in checks {
        if !(value.is_finite() && value > lo && value <= hi) {
            return Err(AlignError::BadOption { name, value, range });
        }
    }
    for (i, v) in o.mean_angle_rad.iter().enumerate() {
        if !(v.is_finite() && v.abs() <= PI) {
            let name = [
                "mean_angle_rad[0]",
                "mean_angle_rad[1]",
                "mean_angle_rad[2]",
                "mean_angle_rad[3]",
            ][i];
            return Err(AlignError::BadOption {
                name,
                value: *v,
                range: "[-pi, pi] rad",
            });
        }
    }
    Ok(())
}

/// [`AlignError::Cancelled`] once the hook [`AlignOptions::cancel`] says so.
fn check_cancel(o: &AlignOptions) -> Result<(), AlignError> {
    match o.cancel.is_some_and(|f| f()) {
        true => Err(AlignError::Cancelled),
        false => Ok(()),
    }
}

/// `x` wrapped to (-pi, pi].
fn wrap(x: f64) -> f64 {
    let y = (x + PI).rem_euclid(2.0 * PI) - PI;
    if y <= -PI {
        y + 2.0 * PI
    } else {
        y
    }
}

/// Estimates every sensor's rotation to its segment frame from walking
/// data (SPEC section 1; method in the module docs and `docs/ALIGNMENT.md`).
///
/// Segments without any IMU reading get `None`. A segment with data that
/// cannot be aligned is an error naming it (or, with
/// [`AlignOptions::partial`], listed in [`Alignment::skipped`]).
pub fn estimate_alignment(
    records: &[Record],
    opts: &AlignOptions,
) -> Result<Alignment, AlignError> {
    check_options(opts)?;
    if records.is_empty() {
        return Err(AlignError::NoSamples);
    }
    let t_ok = records[0].sample.t.is_finite()
        && records
            .windows(2)
            .all(|w| w[1].sample.t > w[0].sample.t && w[1].sample.t.is_finite());
    if !t_ok {
        return Err(AlignError::BadTime);
    }
    let n = records.len();
    let count = |f: fn(&[Record], Segment, usize) -> Option<Vector3<f64>>, s| {
        (0..n).filter(|&k| f(records, s, k).is_some()).count()
    };
    let n_gyr = Segment::ALL.map(|s| count(gyr, s));
    let n_acc = Segment::ALL.map(|s| count(acc, s));
    let present = [0, 1, 2, 3].map(|i| n_gyr[i] > 0 || n_acc[i] > 0);
    if !present.iter().any(|&p| p) {
        return Err(AlignError::NoImu);
    }
    if !present[Segment::Trunk.index() + 1..].iter().any(|&p| p) {
        return Err(AlignError::NoLegImu);
    }
    let quiet = if opts.use_quiet {
        quiet_window(records, &present, opts)
    } else {
        None
    };
    check_cancel(opts)?;
    // One sample has no interval (an audit: it was said to "span 1 s").
    if n < 2 {
        return Err(AlignError::OneSample {
            needed_s: opts.min_walking_s,
        });
    }
    let dt = (records[n - 1].sample.t - records[0].sample.t) / (n - 1) as f64;
    // The most walking the trial can hold: its samples times `dt`. Shorter
    // than needed is said as such (an audit: times of 1e-20 s per sample
    // made the stride lag overflow in `walking_mask`).
    let span_s = n as f64 * dt;
    if span_s < opts.min_walking_s {
        return Err(AlignError::TooShort {
            span_s,
            needed_s: opts.min_walking_s,
        });
    }
    let half = (0.5 * opts.turn_window_s / dt).round() as usize;
    let turning = turning_mask(records, &present, half, opts.turn_max_rate);
    let walking = walking_mask(records, &present, dt, opts);
    check_cancel(opts)?;
    let moving: Vec<usize> = (0..n)
        .filter(|&k| walking[k] && !turning[k] && !quiet.as_ref().is_some_and(|q| q.contains(&k)))
        .collect();
    let walking_s = moving.len() as f64 * dt;
    if walking_s < opts.min_walking_s {
        return Err(AlignError::NoWalking {
            walking_s,
            needed_s: opts.min_walking_s,
        });
    }

    let mut fail: [Option<AlignError>; 4] = [None, None, None, None];
    for s in Segment::ALL {
        let i = s.index();
        if present[i] && n_gyr[i] == 0 {
            fail[i] = Some(AlignError::NoGyro { segment: s });
        } else if present[i] && n_acc[i] == 0 {
            fail[i] = Some(AlignError::NoAcc { segment: s });
        }
    }

    // 1-2. Leg axes (principal axis of the horizontal gyro, optional hinge
    // fit) and their signs.
    let LegAxes {
        axes,
        pca,
        method,
        hinge_res,
        sign_margin,
        axis_ratio,
        gyro_only,
    } = leg_axes(records, &moving, &present, &mut fail, opts);
    check_cancel(opts)?;

    // 3. In-plane zero of the leg sensors, then the trunk (through the thigh).
    let mut out = Alignment {
        quiet: quiet
            .as_ref()
            .map(|q| (records[q.start].sample.t, records[q.end - 1].sample.t)),
        walking_samples: moving.len(),
        turning_samples: turning.iter().filter(|&&t| t).count(),
        not_walking_samples: walking.iter().filter(|&&w| !w).count(),
        ..Default::default()
    };
    let ctx = Ctx {
        records,
        moving: &moving,
        quiet: quiet.as_ref(),
        opts,
    };
    let mut thigh_series = Vec::new();
    for s in LEG {
        let i = s.index();
        let Some(z) = axes[i].filter(|_| fail[i].is_none()) else {
            continue;
        };
        match ctx.in_plane(s, &z, None) {
            Ok((rotation, zero_method, mean, series)) => {
                out.per_segment[i] = Some(SensorAlignment {
                    rotation,
                    axis_method: method[i],
                    zero_method,
                    axis_energy_fraction: ctx.energy_fraction(s, &z),
                    axis_ratio: axis_ratio[i],
                    axis_vs_principal_rad: pca[i].map_or(0.0, |p| p.dot(&z).abs().min(1.0).acos()),
                    gyro_only_weight: gyro_only[i],
                    hinge_residual: hinge_res[i],
                    sign_margin: sign_margin[i],
                    walking_mean_angle_rad: mean,
                });
                if s == Segment::Thigh {
                    thigh_series = series;
                }
            }
            Err(e) => fail[i] = Some(e),
        }
    }
    check_cancel(opts)?;
    let rot = out.per_segment.map(|a| a.map(|a| *a.rotation.matrix()));
    out.leg = Some(detect_leg(records, &moving, &rot, opts.leg_min_score));
    let (tr, th) = (Segment::Trunk.index(), Segment::Thigh.index());
    if present[tr] && fail[tr].is_none() {
        match &out.per_segment[th] {
            None => {
                let thigh = fail[th].clone().map(Box::new);
                fail[tr] = Some(AlignError::TrunkNeedsThigh { thigh });
            }
            Some(t) => match trunk_axis(records, &moving, t.rotation.matrix(), &thigh_series) {
                Some(ta) if ta.corr >= opts.trunk_min_corr && (0.33..=3.0).contains(&ta.gain) => {
                    match ctx.in_plane(Segment::Trunk, &ta.z, Some(ta.up)) {
                        Ok((rotation, zero_method, mean, _)) => {
                            out.per_segment[tr] = Some(SensorAlignment {
                                rotation,
                                axis_method: AxisMethod::GravityHipLink,
                                zero_method,
                                axis_energy_fraction: ctx.energy_fraction(Segment::Trunk, &ta.z),
                                axis_ratio: None,
                                axis_vs_principal_rad: ctx
                                    .principal_deviation(Segment::Trunk, &ta.z),
                                gyro_only_weight: 0.0,
                                hinge_residual: None,
                                sign_margin: ta.corr,
                                walking_mean_angle_rad: mean,
                            })
                        }
                        Err(e) => fail[tr] = Some(e),
                    }
                }
                other => {
                    let (corr, gain) = other.map_or((0.0, 0.0), |t| (t.corr, t.gain));
                    fail[tr] = Some(AlignError::NoWalkingDirection {
                        corr,
                        gain,
                        needed: opts.trunk_min_corr,
                    });
                }
            },
        }
    }
    // Leg errors first: a trunk error may only follow from the thigh's.
    for s in [
        Segment::Thigh,
        Segment::Shank,
        Segment::Foot,
        Segment::Trunk,
    ] {
        if let Some(e) = fail[s.index()].take() {
            if !opts.partial {
                return Err(e);
            }
            out.per_segment[s.index()] = None;
            out.skipped.push((s, e));
        }
    }
    Ok(out)
}

/// What the per-sensor steps share.
struct Ctx<'a> {
    records: &'a [Record],
    moving: &'a [usize],
    quiet: Option<&'a std::ops::Range<usize>>,
    opts: &'a AlignOptions,
}

/// Aligned rotation, zero method, walking mean angle and aligned angle series.
type InPlane = (Rotation3<f64>, ZeroMethod, f64, Vec<(usize, f64)>);

impl Ctx<'_> {
    /// Fraction of the gyro energy about `z` over the moving samples.
    fn energy_fraction(&self, s: Segment, z: &Vector3<f64>) -> f64 {
        let (mut e_z, mut e_all) = (0.0, 0.0);
        for w in self.moving.iter().filter_map(|&k| gyr(self.records, s, k)) {
            e_z += w.dot(z).powi(2);
            e_all += w.norm_squared();
        }
        if e_all > 0.0 {
            e_z / e_all
        } else {
            0.0
        }
    }

    /// Angle (rad) between `z` and the principal gyro axis.
    fn principal_deviation(&self, s: Segment, z: &Vector3<f64>) -> f64 {
        let ws = self.moving.iter().filter_map(|&k| gyr(self.records, s, k));
        principal_axis(ws).map_or(0.0, |(p, _, _, _)| p.dot(z).abs().min(1.0).acos())
    }

    /// Rotation, zero method, walking mean angle and the aligned angle
    /// series of one sensor with axis `z` (and up direction `up`, default:
    /// its mean specific force over the moving samples).
    fn in_plane(
        &self,
        s: Segment,
        z: &Vector3<f64>,
        up: Option<Vector3<f64>>,
    ) -> Result<InPlane, AlignError> {
        let (records, opts) = (self.records, self.opts);
        let up = up.unwrap_or_else(|| self.moving.iter().filter_map(|&k| acc(records, s, k)).sum());
        let frame = provisional(z, &up).ok_or(AlignError::VerticalAxis { segment: s })?;
        let mut series = angle_series(records, s, &frame, self.moving, opts.zero_window_s);
        let walk_mean = series.first().map(|&(_, r)| {
            r + series.iter().map(|(_, p)| wrap(p - r)).sum::<f64>() / series.len() as f64
        });
        let quiet = self.quiet;
        let standing = quiet.and_then(|q| static_angle(records, s, &frame, q.clone()));
        let (delta, zero, mean) = match (standing, walk_mean) {
            (Some(d), Some(w)) if wrap(w - d).abs() < opts.max_standing_offset_rad => {
                (d, quiet_method(records, quiet), wrap(w - d))
            }
            (Some(d), None) => (d, quiet_method(records, quiet), f64::NAN),
            (_, Some(w)) => {
                let target = opts.mean_angle_rad[s.index()];
                (
                    w - target,
                    ZeroMethod::MeanInclination { target_rad: target },
                    target,
                )
            }
            (None, None) => return Err(AlignError::NoAcc { segment: s }),
        };
        for p in series.iter_mut() {
            p.1 -= delta;
        }
        let r = rot_z(delta) * frame;
        Ok((Rotation3::from_matrix_unchecked(r), zero, mean, series))
    }
}

fn quiet_method(records: &[Record], q: Option<&std::ops::Range<usize>>) -> ZeroMethod {
    let q = q.cloned().unwrap_or(0..1);
    ZeroMethod::QuietStanding {
        start_s: records[q.start].sample.t,
        end_s: records[q.end - 1].sample.t,
    }
}
