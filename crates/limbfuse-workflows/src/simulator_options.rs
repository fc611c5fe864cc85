//! A simulator's out-of-range setting named as the option users set it by:
//! the simulators name their configuration fields (`speed_mps`,
//! `turns.angle_rad` in radians), the CLI and the Python package name their
//! options (`--turn-deg` / `turn_deg`, in degrees). An audit found
//! `--turn-deg 1e300` reported as `turns.angle_rad` = a 300-digit number.

use limbfuse_sim::SimError;

/// `turn_deg` / `--turn-deg` when not given: a U-turn (deg).
pub const DEFAULT_TURN_DEG: f64 = 180.0;
/// `turn_s` / `--turn-s` when not given: the duration of one turn (s).
pub const DEFAULT_TURN_S: f64 = 2.5;
/// `remount_deg` / `--remount-deg` when not given: paper 002's 50 deg.
pub const DEFAULT_REMOUNT_DEG: f64 = 50.0;

/// A setting out of range, in the option's name and unit.
#[derive(Debug, Clone, PartialEq)]
pub struct OptionOutOfRange {
    /// The option, words joined by `_` (the Python keyword; the CLI flag is
    /// `--` and the words joined by `-`).
    pub option: &'static str,
    /// The value in the option's unit.
    pub value: f64,
    /// The allowed range in the option's unit.
    pub range: &'static str,
}

impl OptionOutOfRange {
    /// The simulator error `e` as the option a user set, when it is one of
    /// the options of `simulate walking`, `knee` or `calibration`.
    pub fn of(e: &SimError) -> Option<Self> {
        let SimError::OutOfRange { name, value, range } = *e else {
            return None;
        };
        let (option, value, range) = match name {
            "speed_mps" => ("speed", value, range),
            "duration_s" => ("duration", value, "> 0 s"),
            "imu_rate_hz" => ("imu_rate", value, range),
            "turns.duration_s" => ("turn_s", value, "> 0 s"),
            "turns.every_s" => ("turn_every", value, "(the turn's duration, 1e9] s"),
            "turns.angle_rad" => ("turn_deg", value.to_degrees(), "[-1800, 1800] deg"),
            "ap_offset_sd_m" => ("ap_offset_sd_cm", 100.0 * value, "[0, 5] cm"),
            "remount.t_s" => ("remount_at", value, ">= 0 s"),
            "remount.angle_rad" => ("remount_deg", value.to_degrees(), "[-180, 180] deg"),
            "hold_s" => ("hold", value, range),
            "transition_s" => ("transition", value, range),
            "lever_arm_m" => ("lever_arm", value, range),
            _ => return None,
        };
        // (10 significant digits: a value turned into radians and back
        // shows as the user wrote it, 1e9 and not 1.0000000000000001e9)
        let value = format!("{value:.9e}").parse().unwrap_or(value);
        Some(OptionOutOfRange {
            option,
            value,
            range,
        })
    }

    /// The FES simulators' error `e` as the option a user set (`simulate
    /// knee-fes`, `fixed-hip`: an audit found `--rate 1e-300` reported as
    /// `rate_hz` = 301 digits).
    pub fn of_fes(e: &limbfuse_sim::fes_error::FesSimError) -> Option<Self> {
        let limbfuse_sim::fes_error::FesSimError::OutOfRange { name, value, .. } = *e else {
            return None;
        };
        let (option, range) = match name {
            "duration_s" => ("duration", "[1, 3600] s"),
            "rate_hz" => ("rate", "[10, 2000] Hz"),
            "cycles" => ("cycles", "[0, 600] (6 s each)"),
            _ => return None,
        };
        Some(OptionOutOfRange {
            option,
            value,
            range,
        })
    }

    /// The CLI flag: `--turn-deg`.
    pub fn flag(&self) -> String {
        format!("--{}", self.option.replace('_', "-"))
    }
}

/// The gyro drift option of `simulate knee-fes` / `fixed-hip`, given in
/// deg/s, in rad/s: within the simulators' +-1 rad/s (an audit: `--gyro-drift
/// 100` was reported as `gyro_drift = 1.745 ... [-1, 1] rad/s`).
pub fn gyro_drift_rad_s(deg_s: f64) -> Result<f64, OptionOutOfRange> {
    let rad_s = deg_s.to_radians();
    if rad_s.is_finite() && rad_s.abs() <= 1.0 {
        Ok(rad_s)
    } else {
        Err(OptionOutOfRange {
            option: "gyro_drift",
            value: deg_s,
            range: "[-57.3, 57.3] deg/s (1 rad/s)",
        })
    }
}

/// The muscles' activation time constant of `simulate fixed-hip` (s): a
/// positive number (an audit: `--activation-t-a 0` said "a limb needs
/// positive mass").
pub fn activation_t_a_s(t_a: f64) -> Result<f64, OptionOutOfRange> {
    if t_a.is_finite() && t_a > 0.0 {
        Ok(t_a)
    } else {
        Err(OptionOutOfRange {
            option: "activation_t_a",
            value: t_a,
            range: "> 0 s (the muscles' activation time constant, e.g. 0.1)",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_named_as_options_in_their_units() {
        let e = SimError::OutOfRange {
            name: "turns.angle_rad",
            value: core::f64::consts::PI * 20.0,
            range: "[-10 pi, 10 pi] rad",
        };
        let o = OptionOutOfRange::of(&e).unwrap();
        assert_eq!(
            (o.flag().as_str(), o.range),
            ("--turn-deg", "[-1800, 1800] deg")
        );
        assert!((o.value - 3600.0).abs() < 1e-9);
        let e = SimError::OutOfRange {
            name: "ap_offset_sd_m",
            value: 0.5,
            range: "[0, 0.05] m",
        };
        let o = OptionOutOfRange::of(&e).unwrap();
        assert_eq!((o.option, o.value), ("ap_offset_sd_cm", 50.0));
        let other = SimError::OutOfRange {
            name: "g",
            value: 0.0,
            range: "[1, 20] m/s^2",
        };
        assert_eq!(OptionOutOfRange::of(&other), None);
    }

    #[test]
    fn gyro_drift_and_activation_are_checked_in_the_options_unit() {
        assert!((gyro_drift_rad_s(57.0).unwrap() - 57f64.to_radians()).abs() < 1e-15);
        let e = gyro_drift_rad_s(-58.0).unwrap_err();
        assert_eq!((e.flag().as_str(), e.value), ("--gyro-drift", -58.0));
        assert!(gyro_drift_rad_s(f64::INFINITY).is_err());
        assert_eq!(activation_t_a_s(0.1), Ok(0.1));
        for bad in [0.0, -0.1, f64::NAN] {
            assert_eq!(activation_t_a_s(bad).unwrap_err().option, "activation_t_a");
        }
    }
}
