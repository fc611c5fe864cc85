//! A number as messages write it: as Rust prints it, or in exponent form
//! when far from 1 (`1e300`, not 301 digits; an audit found model and
//! parameter messages printing `1e300` digit by digit).

use core::fmt;

/// `f64` for messages: exponent form outside `[1e-4, 1e9)` in magnitude
/// (zero and non-finite values as Rust prints them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShownNumber(pub f64);

impl fmt::Display for ShownNumber {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        if v != 0.0 && v.is_finite() && !(1e-4..1e9).contains(&v.abs()) {
            write!(f, "{v:e}")
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
    }
}
