//! Physical bounds on the entries of an IMU calibration file
//! (`crate::calibration`): finite but absurd values (an audit: an
//! `acc_matrix` diagonal or a `gyro_bias` of 1e308) are refused with the
//! file and key.

use nalgebra::Matrix3;

/// Largest accelerometer scale factor (a singular value of `acc_matrix`)
/// a file may hold, and the smallest is its inverse. MEMS accelerometers'
/// sensitivity is within a few percent of nominal (datasheets: +-3 %; the
/// cross-axis terms +-2 %): a factor of 2 admits any real sensor and refuses
/// a unit slip (g read as m/s^2 is a factor 9.81) or garbage (an audit: a
/// diagonal of 1e308 was accepted).
pub const MAX_ACC_SCALE: f64 = 2.0;
/// Largest gyroscope bias per axis a file may hold (rad/s). MEMS gyroscopes'
/// zero-rate offset is at most a few deg/s over temperature (datasheets:
/// +-5 deg/s = 0.09 rad/s); 1 rad/s (57 deg/s) is ten times that (an audit:
/// a bias of 1e308 was accepted).
pub const MAX_GYRO_BIAS_RAD_S: f64 = 1.0;
/// Largest accelerometer bias per axis a file may hold (m/s^2): zero-g
/// offsets are below 0.5 m/s^2 (datasheets: +-50 mg); 1 g is twenty times
/// that.
pub const MAX_ACC_BIAS_M_S2: f64 = 9.81;

/// The range of a file's top-level `gravity` (m/s^2). Gravity at the
/// Earth's surface is 9.76-9.84 m/s^2 (latitude, altitude, local geology);
/// `limbfuse calibrate` fits to 9.7-9.9 only. A file's value is the norm
/// its fit gave the static readings and is not used when the calibration is
/// applied (`acc_matrix` and `acc_bias` carry the fit), so the bound only
/// has to catch what is not the Earth's gravity in m/s^2: a unit slip (1 in
/// g, 32.17 in ft/s^2, 981 in cm/s^2), 0, a negative or absurd number (an
/// audit: 1e300 was accepted). Some 7 % either side of the Earth's range
/// leaves a file written by other software or by hand with a rounded or
/// differently measured local value readable.
pub const GRAVITY_RANGE_M_S2: (f64, f64) = (9.0, 10.5);

/// What a file's `gravity` out of [`GRAVITY_RANGE_M_S2`] should have been
/// (`None`: within it).
pub(crate) fn check_gravity(gravity: f64) -> Option<String> {
    let (lo, hi) = GRAVITY_RANGE_M_S2;
    if (lo..=hi).contains(&gravity) {
        return None;
    }
    Some(format!(
        "the gravity the fit used, in m/s^2, within {lo} to {hi} (the Earth's surface gravity \
         is 9.76-9.84 m/s^2; found {})",
        limbfuse_core::ShownNumber(gravity)
    ))
}

/// The key of a sensor entry out of its physical range and what was
/// expected (the entry's finiteness is checked before).
pub(crate) fn check(
    acc_bias: &[f64; 3],
    m: &Matrix3<f64>,
    gyro_bias: Option<[f64; 3]>,
) -> Result<(), (&'static str, String)> {
    let shown = |v: f64| limbfuse_core::ShownNumber(v).to_string();
    if let Some(b) = acc_bias.iter().find(|b| b.abs() > MAX_ACC_BIAS_M_S2) {
        return Err((
            "acc_bias",
            format!(
                "each within +-{MAX_ACC_BIAS_M_S2} m/s^2 (a zero-g offset; found {})",
                shown(*b)
            ),
        ));
    }
    let sv = m.singular_values();
    let (lo, hi) = (sv.min(), sv.max());
    if !(lo >= 1.0 / MAX_ACC_SCALE && hi <= MAX_ACC_SCALE) {
        let found = if hi > MAX_ACC_SCALE { hi } else { lo };
        return Err((
            "acc_matrix",
            format!(
                "scale factors (its singular values) within {} to {MAX_ACC_SCALE} \
                 (an accelerometer's sensitivity is within a few percent of nominal; found {})",
                1.0 / MAX_ACC_SCALE,
                shown(found)
            ),
        ));
    }
    if let Some(g) = gyro_bias.and_then(|g| g.into_iter().find(|b| b.abs() > MAX_GYRO_BIAS_RAD_S)) {
        return Err((
            "gyro_bias",
            format!(
                "each within +-{MAX_GYRO_BIAS_RAD_S} rad/s (a zero-rate offset, 57 deg/s; found {})",
                shown(g)
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::calibration::Calibration;

    /// A calibration file with a thigh entry of these values.
    fn file(acc_matrix: &str, gyro_bias: &str, acc_bias: &str) -> String {
        format!(
            "format = \"limbfuse-imu-calibration/1\"\nmodel = \"full\"\ngravity = 9.81\n\
             [sensors.thigh]\nacc_bias = {acc_bias}\nacc_matrix = {acc_matrix}\ngyro_bias = {gyro_bias}\n"
        )
    }

    const M: &str = "[[1.01, 0.0, 0.0], [0.0, 0.99, 0.0], [0.0, 0.0, 1.0]]";
    const G: &str = "[0.01, 0.0, -0.02]";
    const B: &str = "[0.1, 0.0, 0.0]";

    /// An audit (session 28): a file's top-level `gravity` of 1e300, 0, a
    /// negative number or 1 (g for m/s^2) was accepted (1e300, 0 and
    /// negatives were refused as "a finite number > 0" only when not
    /// finite or not positive). Now an error naming the file, the key and
    /// the range; 9.0 and 10.5 still read.
    #[test]
    fn a_gravity_off_the_earths_is_refused_with_the_key() {
        let p = Path::new("c.toml");
        for ok in ["9.0", "9.81", "10.5"] {
            let text = file(M, G, B).replace("gravity = 9.81", &format!("gravity = {ok}"));
            let c = Calibration::from_toml(&text, p);
            assert!(c.is_ok(), "{ok}: {:?}", c.err().map(|e| e.to_string()));
        }
        for bad in [
            "1e300", "0.0", "-9.81", "1.0", "32.17", "981.0", "8.99", "10.51",
        ] {
            let text = file(M, G, B).replace("gravity = 9.81", &format!("gravity = {bad}"));
            let e = Calibration::from_toml(&text, p).unwrap_err().to_string();
            assert!(
                e.starts_with("c.toml:") && e.contains("`gravity`") && e.contains("9 to 10.5"),
                "{bad}: {e}"
            );
            assert!(!e.contains("00000000000"), "{e}");
        }
    }

    /// An audit: an `acc_matrix` diagonal of 1e308 or a `gyro_bias` of 1e308
    /// was accepted. Now an error naming the file and the key, the number
    /// short.
    #[test]
    fn absurd_scale_factors_and_biases_are_refused_with_the_key() {
        let p = Path::new("c.toml");
        let ok = Calibration::from_toml(&file(M, G, B), p);
        assert!(ok.is_ok(), "{:?}", ok.err().map(|e| e.to_string()));
        let cases = [
            (
                file(
                    "[[1e308, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]",
                    G,
                    B,
                ),
                "sensors.thigh.acc_matrix",
            ),
            (
                file(
                    "[[9.81, 0.0, 0.0], [0.0, 9.81, 0.0], [0.0, 0.0, 9.81]]",
                    G,
                    B,
                ),
                "sensors.thigh.acc_matrix",
            ),
            (file(M, "[1e308, 0.0, 0.0]", B), "sensors.thigh.gyro_bias"),
            (file(M, G, "[0.0, -1e308, 0.0]"), "sensors.thigh.acc_bias"),
        ];
        for (text, key) in cases {
            let e = Calibration::from_toml(&text, p).unwrap_err().to_string();
            assert!(e.starts_with("c.toml:") && e.contains(key), "{e}");
            assert!(!e.contains("00000000000"), "{e}");
        }
    }
}
