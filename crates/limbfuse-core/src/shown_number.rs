//! A number as messages write it: as Rust prints it, or in exponent form
//! when far from 1 (`1e300`, not 301 digits; an audit found model and
//! parameter messages printing `1e300` digit by digit), and to 12
//! significant digits (`2.3`, not `2.3000000000000003`: a time stamp
//! computed as `k * dt`, as numpy's and most loggers' are).

use core::fmt;

/// `f64` for messages: exponent form outside `[1e-4, 1e9)` in magnitude
/// (zero and non-finite values as Rust prints them); inside, rounded to 12
/// significant digits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShownNumber(pub f64);

impl fmt::Display for ShownNumber {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        if v != 0.0 && v.is_finite() && !(1e-4..1e9).contains(&v.abs()) {
            write!(f, "{v:e}")
        } else if v != 0.0 && v.is_finite() {
            // 10^(11 - e) for the decimal exponent e in -4..=8: an exact
            // power of ten (<= 1e15), and |v| times it < 1e12 < 2^53, so the
            // rounded product is exact and the division the nearest double
            // of the 12-digit decimal.
            const POW10: [f64; 13] = [
                1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
            ];
            let e = libm::floor(libm::log10(libm::fabs(v))) as i32;
            let scale = POW10[(11 - e).clamp(3, 15) as usize - 3];
            write!(f, "{}", libm::round(v * scale) / scale)
        } else {
            write!(f, "{v}")
        }
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::ShownNumber;

    #[test]
    fn far_from_one_in_exponent_form_else_as_printed() {
        let s = |v: f64| std::format!("{}", ShownNumber(v));
        assert_eq!(s(1e300), "1e300");
        assert_eq!(s(-1e-300), "-1e-300");
        assert_eq!(s(0.5), "0.5");
        assert_eq!(s(123456.0), "123456");
        assert_eq!(s(0.0), "0");
        assert_eq!(s(f64::NAN), "NaN");
        assert_eq!(s(2.3000000000000003), "2.3");
        assert_eq!(s(230.0 * 0.01), "2.3");
        assert_eq!(s(-0.1 - 0.2), "-0.3");
        assert_eq!(s(40.142572795869576), "40.1425727959");
        assert_eq!(s(123456789.0), "123456789");
        assert_eq!(s(0.000123456789012345), "0.000123456789012");
        assert_eq!(s(1.5e-4), "0.00015");
    }
}
