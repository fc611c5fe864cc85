//! Medio-lateral axes of the leg sensors (thigh, shank, foot) and their
//! signs: the principal axis of the horizontal part of each gyro signal,
//! optionally refined by the knee/ankle hinge fit, then the gait sign rules.

use limbfuse_core::{Record, Segment};
use nalgebra::Vector3;

use super::axis::{gyro_only_blend, hinge_fit, principal_axis, up_track};
use super::series::gyr;
use super::sign::{choose_signs, peak_score, Evidence};
use super::{AlignError, AlignOptions, AxisMethod};

/// The leg segments, proximal to distal.
pub(crate) const LEG: [Segment; 3] = [Segment::Thigh, Segment::Shank, Segment::Foot];

/// Axes (signed, pointing right), principal axes and quality per segment
/// (trunk entries stay `None`/default).
pub(crate) struct LegAxes {
    pub axes: [Option<Vector3<f64>>; 4],
    pub pca: [Option<Vector3<f64>>; 4],
    pub method: [AxisMethod; 4],
    pub hinge_res: [Option<f64>; 4],
    pub sign_margin: [f64; 4],
    /// Second / largest eigenvalue of the horizontal gyro energy.
    pub axis_ratio: [Option<f64>; 4],
    /// Weight of the gyro-only principal axis in the axis (0: the
    /// horizontal one alone, 1: the gyro-only one), see [`gyro_only_blend`].
    pub gyro_only: [f64; 4],
}

/// Finds the leg axes over the `moving` samples; a segment that fails gets
/// its error in `fail` (segments already failed or not `present` are skipped).
pub(crate) fn leg_axes(
    records: &[Record],
    moving: &[usize],
    present: &[bool; 4],
    fail: &mut [Option<AlignError>; 4],
    opts: &AlignOptions,
) -> LegAxes {
    let n = records.len();
    // Principal axes of the horizontal gyro, then the optional hinge fit.
    let mut axes: [Option<Vector3<f64>>; 4] = [None; 4];
    let mut pca: [Option<Vector3<f64>>; 4] = [None; 4];
    let mut method = [AxisMethod::Principal; 4];
    let mut hinge_res: [Option<f64>; 4] = [None; 4];
    let mut axis_ratio: [Option<f64>; 4] = [None; 4];
    let mut gyro_only = [0.0; 4];
    for s in LEG {
        let i = s.index();
        if !present[i] || fail[i].is_some() {
            continue;
        }
        // Leave out the rate about the vertical (turning, axial rotation of
        // the leg): the medio-lateral axis is horizontal at every instant.
        let up = if opts.horizontal {
            up_track(records, s, opts.up_tau_s)
        } else {
            vec![None; n]
        };
        let ws = moving.iter().filter_map(|&k| {
            let w = gyr(records, s, k)?;
            Some(up[k].map_or(w, |v| w - v * w.dot(&v)))
        });
        match principal_axis(ws) {
            Some((_, _, rms, ratio)) if rms >= opts.min_gyro_rms && ratio > opts.max_axis_ratio => {
                fail[i] = Some(AlignError::AxisUndetermined {
                    segment: s,
                    ratio,
                    max: opts.max_axis_ratio,
                })
            }
            Some((v, _, rms, ratio)) if rms >= opts.min_gyro_rms => {
                let raw = moving.iter().filter_map(|&k| gyr(records, s, k));
                let (z, weight) = match principal_axis(raw) {
                    Some((r, ..)) if opts.horizontal => {
                        gyro_only_blend(&v, &r, opts.gyro_axis_max_tilt_rad)
                    }
                    _ => (v, 0.0),
                };
                pca[i] = Some(z);
                gyro_only[i] = weight;
                axis_ratio[i] = Some(ratio);
            }
            Some((_, _, rms, _)) => {
                fail[i] = Some(AlignError::TooLittleMotion {
                    segment: s,
                    gyro_rms: rms,
                    needed: opts.min_gyro_rms,
                })
            }
            // Every gyro sample is in the quiet period or a turn: report
            // the RMS over all of them.
            None => {
                let all = (0..n).filter_map(|k| gyr(records, s, k));
                let gyro_rms = principal_axis(all).map_or(0.0, |p| p.2);
                fail[i] = Some(AlignError::TooLittleMotion {
                    segment: s,
                    gyro_rms,
                    needed: opts.min_gyro_rms,
                })
            }
        }
        axes[i] = pca[i];
    }
    if opts.hinge {
        let pairs: Vec<(Segment, Segment)> = LEG
            .windows(2)
            .filter(|w| pca[w[0].index()].is_some() && pca[w[1].index()].is_some())
            .map(|w| (w[0], w[1]))
            .collect();
        if let Some(fit) = hinge_fit(records, &pairs, &pca, opts.hinge_max_samples) {
            for s in LEG {
                let i = s.index();
                let (Some(h), Some(p)) = (fit.axes[i], pca[i]) else {
                    continue;
                };
                if h.dot(&p).abs().min(1.0).acos() > opts.max_hinge_deviation_rad {
                    continue;
                }
                axes[i] = Some(h);
                let mut res2 = Vec::new();
                let (mut knee, mut ankle) = (false, false);
                for (p, &(a, b)) in pairs.iter().enumerate() {
                    if a == s || b == s {
                        res2.push(fit.rms[p] * fit.rms[p]);
                        knee |= a == Segment::Thigh;
                        ankle |= b == Segment::Foot;
                    }
                }
                hinge_res[i] = Some((res2.iter().sum::<f64>() / res2.len() as f64).sqrt());
                method[i] = AxisMethod::Hinge { knee, ankle };
            }
        }
    }

    // Signs.
    let rates: [Vec<Option<f64>>; 4] = Segment::ALL.map(|s| match axes[s.index()] {
        Some(j) => moving
            .iter()
            .map(|&k| gyr(records, s, k).map(|w| w.dot(&j)))
            .collect(),
        None => Vec::new(),
    });
    let evidence = [0, 1, 2, 3].map(|i| {
        axes[i].map(|_| {
            let r: Vec<f64> = rates[i].iter().flatten().copied().collect();
            Evidence {
                peak: peak_score(&r),
            }
        })
    });
    let times: Vec<f64> = moving.iter().map(|&k| records[k].sample.t).collect();
    let (signs, margins) = choose_signs(&evidence, &rates, &times);
    for i in 0..4 {
        axes[i] = axes[i].map(|j| j * signs[i]);
        if axes[i].is_some() && fail[i].is_none() && margins[i] < opts.min_sign_margin {
            fail[i] = Some(AlignError::SignUndetermined {
                segment: Segment::ALL[i],
                margin: margins[i],
                min: opts.min_sign_margin,
            });
        }
    }

    LegAxes {
        axes,
        pca,
        method,
        hinge_res,
        sign_margin: margins,
        axis_ratio,
        gyro_only,
    }
}
