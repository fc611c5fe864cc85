//! Exact reading of the plain decimal cells limbfuse writes (`-0.16345629591913766`:
//! a sign, digits, a point, digits; no exponent) without a general float
//! parser: the digits are read eight at a time into an integer `m` with `k`
//! digits after the point, and `m / 10^k` is rounded to the nearest `f64`
//! (ties to even) by integer division, which is exact by construction.
//!
//! Anything else (an exponent, more than 19 significant digits, more than
//! 21 digits after the point, no digit, another byte) is left to the
//! general parser (`crate::cell_format::parse_number`): [`parse`] returns
//! `None` for it, never a different value.

/// `10^k` for `k` up to [`MAX_FRACTION_DIGITS`].
const POW10: [u128; 22] = {
    let mut t = [1u128; 22];
    let mut i = 1;
    while i < 22 {
        t[i] = t[i - 1] * 10;
        i += 1;
    }
    t
};

/// `10^k` as `f64` (exact for `k <= 22`).
const POW10_F64: [f64; 22] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21,
];

/// Most digits after the point: `m * 2^s` with the 55-bit quotient and
/// `10^21 < 2^70` stays below `2^127`.
const MAX_FRACTION_DIGITS: usize = 21;

/// Most significant digits: `m < 10^19 < 2^64`.
const MAX_SIGNIFICANT_DIGITS: u32 = 19;

/// The value of `cell` when it is a plain decimal this module reads
/// exactly; `None` for any other text (not an error: the caller then asks
/// the general parser).
#[inline]
pub(crate) fn parse(cell: &[u8]) -> Option<f64> {
    let (negative, digits) = match cell.first()? {
        b'-' => (true, &cell[1..]),
        b'+' => (false, &cell[1..]),
        _ => (false, cell),
    };
    let mut m = 0u64;
    let mut significant = 0u32;
    let mut i = read_digits(digits, 0, &mut m, &mut significant)?;
    let int_digits = i;
    let mut fraction = 0;
    if i < digits.len() {
        if digits[i] != b'.' {
            return None;
        }
        let start = i + 1;
        i = read_digits(digits, start, &mut m, &mut significant)?;
        if i != digits.len() {
            return None;
        }
        fraction = i - start;
        if fraction > MAX_FRACTION_DIGITS {
            return None;
        }
    }
    if int_digits + fraction == 0 {
        return None;
    }
    let v = quotient(m, fraction)?;
    Some(if negative { -v } else { v })
}

/// Reads the ASCII digits of `s` from `at` into `m` (`m * 10 + d`),
/// counting the significant ones (from the first non-zero digit); returns
/// where they end, `None` past [`MAX_SIGNIFICANT_DIGITS`].
#[inline]
fn read_digits(s: &[u8], mut at: usize, m: &mut u64, significant: &mut u32) -> Option<usize> {
    while let Some(chunk) = s.get(at..at + 8) {
        let word = u64::from_le_bytes(chunk.try_into().ok()?);
        if !all_digits(word) {
            break;
        }
        if *m != 0 || *significant != 0 {
            *significant += 8;
        } else {
            let value = eight_digits(word);
            if value != 0 {
                *significant = 8 - leading_zero_digits(word);
            }
        }
        if *significant > MAX_SIGNIFICANT_DIGITS {
            return None;
        }
        *m = *m * 100_000_000 + eight_digits(word);
        at += 8;
    }
    while let Some(&b) = s.get(at) {
        let d = b.wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        if *m != 0 || d != 0 {
            *significant += 1;
            if *significant > MAX_SIGNIFICANT_DIGITS {
                return None;
            }
        }
        *m = *m * 10 + u64::from(d);
        at += 1;
    }
    Some(at)
}

/// All eight bytes of `word` are ASCII digits.
#[inline]
fn all_digits(word: u64) -> bool {
    const ZEROS: u64 = 0x3030_3030_3030_3030;
    const SIXES: u64 = 0x0606_0606_0606_0606;
    const HIGH: u64 = 0xF0F0_F0F0_F0F0_F0F0;
    (word & HIGH) == ZEROS && (word.wrapping_add(SIXES) & HIGH) == ZEROS
}

/// The value of eight ASCII digits, the first in the lowest byte.
#[inline]
fn eight_digits(word: u64) -> u64 {
    const PAIRS: u64 = 0x0000_00FF_0000_00FF;
    let v = word - 0x3030_3030_3030_3030;
    // Each byte <= 9: fits in 63 bits.
    let v = (v * 10) + (v >> 8);
    // The products wrap on purpose: only bits 32..64 are kept.
    let high = (v & PAIRS).wrapping_mul(100 + (1_000_000 << 32));
    let low = ((v >> 16) & PAIRS).wrapping_mul(1 + (10_000 << 32));
    (high.wrapping_add(low) >> 32) & 0xFFFF_FFFF
}

/// How many of the eight digits of `word` (first in the lowest byte) are
/// leading `0`s (`word` not all zeros).
#[inline]
fn leading_zero_digits(word: u64) -> u32 {
    let nonzero = word ^ 0x3030_3030_3030_3030;
    nonzero.trailing_zeros() / 8
}

/// `m / 10^k` rounded to the nearest `f64`, ties to even (`k <=`
/// [`MAX_FRACTION_DIGITS`]); `None` for the few `m`, `k` this does not
/// cover (a huge `m` with a short fraction).
#[inline]
fn quotient(m: u64, k: usize) -> Option<f64> {
    if m == 0 {
        return Some(0.0);
    }
    if k == 0 {
        // `as` rounds to nearest, ties to even.
        return Some(m as f64);
    }
    if m <= 1 << 53 {
        // Clinger's fast path: both exact, one correctly rounded division.
        return Some(m as f64 / POW10_F64[k]);
    }
    let d = POW10[k];
    let d_bits = 128 - d.leading_zeros() as i32;
    let m_bits = 64 - m.leading_zeros() as i32;
    // Scale so that the quotient has 55 or 56 bits (2 or 3 below the 53 kept).
    let s = 55 + d_bits - m_bits;
    if s < 0 {
        return None;
    }
    let n = u128::from(m) << s;
    let q = n / d;
    let exact = n % d == 0;
    let q_bits = 128 - q.leading_zeros() as i32;
    let shift = q_bits - 53;
    let mut mantissa = (q >> shift) as u64;
    let rest = q & ((1u128 << shift) - 1);
    let half = 1u128 << (shift - 1);
    if rest > half || (rest == half && (!exact || mantissa & 1 == 1)) {
        mantissa += 1;
    }
    // `mantissa` <= 2^53, exact as f64; the scale is a power of two in the
    // normal range (the value is between 2^53 / 10^21 and 2^64).
    let exponent = shift - s;
    let scale = f64::from_bits(((exponent + 1023) as u64) << 52);
    Some(mantissa as f64 * scale)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn agrees(s: &str) {
        if let Some(v) = parse(s.as_bytes()) {
            let want: f64 = s.parse().unwrap();
            assert_eq!(v.to_bits(), want.to_bits(), "{s}");
        }
    }

    #[test]
    fn reads_what_the_writers_write() {
        assert_eq!(parse(b"-0.16345629591913766"), Some(-0.16345629591913766));
        assert_eq!(parse(b"0.0018995727227811793"), Some(0.0018995727227811793));
        assert_eq!(parse(b"11.88262327856739"), Some(11.88262327856739));
        assert_eq!(parse(b"0.0").map(f64::to_bits), Some(0f64.to_bits()));
        assert_eq!(parse(b"-0.0").map(f64::to_bits), Some((-0f64).to_bits()));
        assert_eq!(parse(b"12"), Some(12.0));
        assert_eq!(parse(b".5"), Some(0.5));
        assert_eq!(parse(b"5."), Some(5.0));
    }

    #[test]
    fn leaves_other_texts_to_the_general_parser() {
        for s in [
            "999999999999999999.9",
            "0.999999999999999999999",
            "1844674407370955161.5",
            "", "-", "+", ".", "-.", "1e5", "1.5e-3", "inf", "NaN", "1.2.3", "1 ", " 1", "1,2",
            "0x1", "12345678901234567890.5", "0.1234567890123456789012",
        ] {
            assert_eq!(parse(s.as_bytes()), None, "{s:?}");
        }
    }

    /// Halfway cases (ties to even) and their neighbours, with a fraction
    /// so that they take the integer division.
    #[test]
    fn ties_round_to_even_as_std_does() {
        for s in [
            "9007199254740993.0",
            "9007199254740995.0",
            "9007199254740993.00",
            "4503599627370496.5",
            "4503599627370497.5",
            "4503599627370496.500",
            "4503599627370496.501",
            "4503599627370496.499",
            "2251799813685248.25",
            "2251799813685248.75",
            "2251799813685249.25",
            "18014398509481985.0",
            "18014398509481987.0",
            "18014398509481986.0",
            "-9007199254740993.0",
            "0.30000000000000004",
            "0.1",
            "9999999999999999999",
            "0.000000000000000000001",
            "0.9999999999999999999",
        ] {
            let want: f64 = s.parse().unwrap();
            assert_eq!(parse(s.as_bytes()).map(f64::to_bits), Some(want.to_bits()), "{s}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]

        /// Random digit strings of every length it takes: the same value as `std`.
        #[test]
        fn agrees_with_std_on_digit_strings(s in "[-+]?[0-9]{0,20}(\\.[0-9]{0,22})?") {
            agrees(&s);
        }

        /// Shortest round-trip texts of random doubles (what limbfuse writes),
        /// in plain notation: the same bits.
        #[test]
        fn reads_written_doubles_back_exactly(bits in any::<u64>()) {
            let v = f64::from_bits(bits);
            prop_assume!(v.is_finite());
            let text = format!("{v}");
            agrees(&text);
            let mut b = ryu::Buffer::new();
            agrees(b.format_finite(v));
        }

        /// Values of everyday magnitudes written with 15-19 digits.
        #[test]
        fn agrees_with_std_on_long_fractions(m in 0u64..10_000_000_000_000_000_000, k in 0usize..22) {
            let digits = m.to_string();
            let s = if k >= digits.len() {
                format!("0.{}{}", "0".repeat(k - digits.len()), digits)
            } else {
                format!("{}.{}", &digits[..digits.len() - k], &digits[digits.len() - k..])
            };
            let want: f64 = s.parse().unwrap();
            let got = parse(s.as_bytes());
            if k <= MAX_FRACTION_DIGITS {
                prop_assert!(got.is_some() || m.leading_zeros() < 9, "{}", s);
            }
            if let Some(v) = got {
                prop_assert_eq!(v.to_bits(), want.to_bits(), "{}", s);
            }
        }
    }
}
