//! The flexion side pooled over windows ([`super::sign::FlexionEvidence`])
//! with a trusted window between untrusted ones (ours, 2026-12-05).

use nalgebra::Vector3;

use super::sign::{gyro_angle_moments, FlexionEvidence};
use super::window::{Ring, Slot};
use super::*;

const DT: f64 = 0.01;
const N: usize = 300;

/// A 3 s window whose knee angle about the thigh's x (the shank's gyro
/// still) is `sign * 40 deg * max(0, sin)^3` at 0.5 Hz: spikes towards
/// `sign`, so the gyro angle's skewness has the sign of `sign`.
fn window(sign: f64) -> Ring {
    let mut ring = Ring::new(N);
    let (a, w) = (40f64.to_radians(), core::f64::consts::PI);
    for i in 0..N {
        let t = i as f64 * DT;
        let s = libm::sin(w * t);
        let rate = if s > 0.0 {
            sign * a * 3.0 * s * s * libm::cos(w * t) * w
        } else {
            0.0
        };
        ring.push(Slot {
            t,
            gyr: [Vector3::new(rate, 0.0, 0.0), Vector3::zeros()],
            acc: [Vector3::zeros(); 2],
            gyr_ok: true,
            acc_ok: true,
        });
    }
    ring
}

fn axes(side: f64) -> Geometry {
    Geometry {
        axis: [Vector3::x() * side, Vector3::x() * side],
        position: [Vector3::new(0.0, 0.0, 0.2), Vector3::new(0.0, 0.0, -0.2)],
        acc_scale: 1.0,
    }
}

/// Pools one window as `end_window` does and returns the axes' side (+1:
/// the knee flexes to positive angles about +x).
fn pool(
    ev: &mut FlexionEvidence,
    ring: &Ring,
    old: Option<f64>,
    side: f64,
    trusted: Option<bool>,
) -> f64 {
    let mut g = axes(side);
    let old = old.map(axes);
    pool_into(
        ev,
        ring,
        old.as_ref(),
        &mut g,
        trusted,
        AngleZero::SensorPositions,
    );
    g.axis[0].x
}

/// Pools `ring` (no level-only window) into `g`, the axes before it `old`.
fn pool_into(
    ev: &mut FlexionEvidence,
    ring: &Ring,
    old: Option<&Geometry>,
    g: &mut Geometry,
    trusted: Option<bool>,
    zero: AngleZero,
) {
    ev.pool_window(ring, old, g, false, trusted, zero);
}

/// Found by reading the code (2026-12-05): four untrusted windows of a
/// knee held flexed (gyro-angle skewness towards extension, the wrong sign)
/// pooled `S` for the extension side; a trusted, uncommitted window then
/// read the flexion side from the accelerometer level, which only turned
/// the sum to `-S`, so the next untrusted window flipped the knee back,
/// although its own skewness was for the flexion side. Expected: the
/// trusted side stands against the earlier windows and the later ones.
#[test]
fn a_trusted_flexion_side_is_not_undone_by_earlier_skewness() {
    let (wrong, right) = (window(-1.0), window(1.0));
    let x = axes(1.0);
    assert!(gyro_angle_moments(&wrong, &x).1 < 0.0);
    assert!(gyro_angle_moments(&right, &x).1 > 0.0);
    let mut ev = FlexionEvidence::default();
    let mut side = pool(&mut ev, &wrong, None, 1.0, Some(false));
    assert_eq!(side, -1.0, "the skewness picks the extension side");
    for _ in 0..3 {
        side = pool(&mut ev, &wrong, Some(side), side, Some(false));
    }
    assert_eq!(side, -1.0);
    // A trusted window reads the flexion side from the level: `identify`
    // gives both axes turned.
    side = pool(&mut ev, &right, Some(side), -side, Some(true));
    assert_eq!(side, 1.0);
    side = pool(&mut ev, &right, Some(side), side, Some(false));
    assert_eq!(
        side, 1.0,
        "a window with the flexion side's skewness flipped the knee"
    );
    side = pool(&mut ev, &wrong, Some(side), side, Some(false));
    assert_eq!(side, 1.0, "an untrusted window overturned the trusted side");
}

/// With the paper's zero a trusted window does not read the side (no
/// level): the skewness keeps choosing it.
#[test]
fn with_the_paper_zero_the_skewness_still_pools() {
    let mut ev = FlexionEvidence::default();
    let mut g = axes(1.0);
    pool_into(
        &mut ev,
        &window(1.0),
        None,
        &mut g,
        Some(true),
        AngleZero::PaperC,
    );
    let old = g;
    pool_into(
        &mut ev,
        &window(-1.0),
        Some(&old),
        &mut g,
        Some(false),
        AngleZero::PaperC,
    );
    assert_eq!(g.axis[0].x, -1.0);
}

/// An anchor belongs to its pair of sides (2026-12-05, on merging): when
/// the open relative sign changes the pair (one axis turned), the new
/// pair's skewness counts again, as its sum starts again.
#[test]
fn a_new_pair_of_sides_is_not_held_by_the_old_anchor() {
    let mut ev = FlexionEvidence::default();
    let mut side = pool(&mut ev, &window(1.0), None, 1.0, Some(true));
    assert_eq!(side, 1.0);
    // The next window turns only the shank's axis: another pair.
    let old = axes(side);
    let mut g = axes(side);
    g.axis[1] = -g.axis[1];
    pool_into(
        &mut ev,
        &window(-1.0),
        Some(&old),
        &mut g,
        Some(false),
        AngleZero::SensorPositions,
    );
    side = g.axis[0].x;
    assert_eq!(side, -1.0, "the new pair's own skewness chose no side");
}
