//! The ranges of a human body that trial metadata and flags are checked
//! against before a method is built (one place: `chain`, `knee-kinematic`,
//! `lowback-speed` and `imm-bslip` read body sizes). A value outside is an
//! error naming the key or flag (an audit: `# height_m: 1e300` gave a
//! walking speed of 7e149 m/s with exit 0).

/// Adult body heights (m).
pub const BODY_HEIGHT_M: (f64, f64) = (1.0, 2.5);
/// Greater-trochanter heights, i.e. leg (rest) lengths (m): 0.530 x the
/// body heights above (Winter 2009), widened to whole decimetres.
pub const LEG_LENGTH_M: (f64, f64) = (0.5, 1.4);
/// Lower-back sensor heights above the floor (m): a sensor at L3-L5 of
/// adults of 1.2-2.2 m sits at about 0.53-0.6 of the body height.
pub const LOWER_BACK_SENSOR_M: (f64, f64) = (0.5, 1.4);
/// Body masses (kg).
pub const MASS_KG: (f64, f64) = (20.0, 250.0);

/// `v` when within `(lo, hi)` (inclusive).
pub fn within(v: f64, (lo, hi): (f64, f64)) -> Option<f64> {
    (lo..=hi).contains(&v).then_some(v)
}
