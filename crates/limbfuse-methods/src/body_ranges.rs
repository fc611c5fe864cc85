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

/// A body mass from a flag or option `name` (kg): the value, or the message
/// "`name V`: expected a human's body mass, 20 to 250 kg".
pub fn mass_kg(name: &str, v: f64) -> Result<f64, String> {
    human(name, v, MASS_KG, "body mass", "kg")
}

/// A leg (rest) length from a flag or option `name` (m), as [`mass_kg`].
pub fn leg_length_m(name: &str, v: f64) -> Result<f64, String> {
    human(name, v, LEG_LENGTH_M, "leg (rest) length", "m")
}

fn human(name: &str, v: f64, range: (f64, f64), what: &str, unit: &str) -> Result<f64, String> {
    within(v, range).ok_or_else(|| {
        format!(
            "{name} {}: expected a human's {what}, {} to {} {unit}",
            crate::shown(v),
            range.0,
            range.1
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn body_sizes_outside_a_humans_are_named() {
        assert_eq!(mass_kg("--mass", 70.0), Ok(70.0));
        assert_eq!(
            mass_kg("--mass", 1e9).unwrap_err(),
            "--mass 1e9: expected a human's body mass, 20 to 250 kg"
        );
        assert_eq!(leg_length_m("leg_length", 0.95), Ok(0.95));
        assert!(leg_length_m("leg_length", f64::NAN)
            .unwrap_err()
            .starts_with("leg_length NaN: expected a human's leg (rest) length, 0.5 to 1.4 m"));
    }
}
