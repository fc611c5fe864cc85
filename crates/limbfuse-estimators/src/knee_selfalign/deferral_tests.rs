//! A first window without a flexion axis is not taken
//! ([`super::KneeSelfAlign::defers`], ours, 2026-12-05).

use nalgebra::Vector3;

use super::window::Slot;
use super::*;

const DT: f64 = 0.01;
const G: f64 = 9.81;

/// A window of `n` samples from `t0`: both segments upright (gravity
/// along their z) turning about z at unrelated rates, with a small wobble
/// about x and y that no common hinge explains (a turn on the spot).
fn turn(t0: f64, n: usize) -> Vec<Slot> {
    (0..n)
        .map(|i| {
            let t = t0 + i as f64 * DT;
            Slot {
                t,
                gyr: [
                    Vector3::new(
                        1.8 * libm::sin(7.1 * t),
                        1.4 * libm::cos(5.3 * t),
                        2.5 + 0.5 * libm::sin(1.3 * t),
                    ),
                    Vector3::new(
                        0.2 * libm::cos(6.7 * t),
                        0.3 * libm::sin(4.1 * t),
                        2.0 + 0.6 * libm::cos(2.9 * t),
                    ),
                ],
                acc: [
                    Vector3::new(0.8 * libm::sin(3.1 * t), 0.6 * libm::cos(2.3 * t), G),
                    Vector3::new(0.7 * libm::cos(3.7 * t), 0.9 * libm::sin(1.9 * t), G),
                ],
                gyr_ok: true,
                acc_ok: true,
            }
        })
        .collect()
}

fn run_window(est: &mut KneeSelfAlign, slots: &[Slot]) {
    for s in slots {
        est.window.push(*s);
    }
    est.end_window();
}

fn params() -> KneeSelfAlignParams {
    KneeSelfAlignParams {
        window: 300,
        ..Default::default()
    }
}

#[test]
fn a_first_window_without_a_flexion_axis_is_deferred_once() {
    let mut est = KneeSelfAlign::new(params()).unwrap();
    run_window(&mut est, &turn(0.0, 300));
    // The window identified eq 2's axes, but showed no flexion: not taken.
    assert!(est.geometry().is_none(), "{:?}", est.geometry());
    assert!(est.geometry_or_deferred().is_some());
    assert_eq!(est.last_window().0, WindowStatus::Unobservable);
    // A second such window is taken (a recording that never shows a
    // flexion axis still gets an angle, one window later).
    run_window(&mut est, &turn(3.0, 300));
    assert!(est.geometry().is_some());
    assert_eq!(est.last_window().0, WindowStatus::Identified);
    assert_eq!(est.rms[2], UprightAxes::NoFlexion.code());
}

#[test]
fn a_window_without_a_flexion_axis_after_an_identified_one_keeps_the_axes() {
    let mut est = KneeSelfAlign::new(params()).unwrap();
    let g = Geometry {
        axis: [Vector3::x(), Vector3::x()],
        position: [Vector3::new(0.0, 0.0, 0.2), Vector3::new(0.0, 0.0, -0.2)],
        acc_scale: 1.0,
    };
    est.geometry = Some(g);
    run_window(&mut est, &turn(0.0, 300));
    // Not a first window: the previous axes are kept, nothing deferred.
    assert!(est.deferred.is_none());
    assert_eq!(est.geometry().map(|g| g.axis), Some(g.axis));
}
