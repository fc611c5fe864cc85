//! Numeric cells: written as the shortest decimal that reads back bit for
//! bit (`zmij`, with `e16` for `e+16`: the same text as `ryu` wrote before,
//! checked by a test),
//! read by `fast-float2` (correctly rounded, the same value as
//! `str::parse::<f64>`, also checked by a test); a missing value is an
//! empty cell.

use std::io::{self, Write};

/// Appends `,` and the cell for `value` to `out`.
#[inline]
pub(crate) fn push_cell(out: &mut Vec<u8>, buf: &mut zmij::Buffer, value: Option<f64>) {
    out.push(b',');
    push_value(out, buf, value);
}

/// Integers below this magnitude are written by `itoa` + `.0` (exact:
/// every integer below 2^53 is a double, and its shortest round-trip
/// decimal is itself; `ryu` wrote them so for magnitudes below 1e16).
const INTEGER_FAST_PATH: f64 = 1e15;

/// Appends the cell for `value` (no separator).
#[inline]
pub(crate) fn push_value(out: &mut Vec<u8>, buf: &mut zmij::Buffer, value: Option<f64>) {
    let Some(v) = value else { return };
    if !v.is_finite() {
        return;
    }
    // `as` truncates toward zero (one instruction; `f64::trunc` is a libm
    // call on baseline x86-64).
    let integer = v as i64;
    if v.abs() < INTEGER_FAST_PATH && integer as f64 == v {
        // Flags, counts and zeros: common in diagnostics.
        if v.is_sign_negative() {
            out.push(b'-');
        }
        push_short(
            out,
            itoa::Buffer::new()
                .format(integer.unsigned_abs())
                .as_bytes(),
        );
        out.extend_from_slice(b".0");
        return;
    }
    let text = buf.format_finite(v).as_bytes();
    // `zmij` writes a positive exponent as `e+16`, `ryu` as `e16`: keep the
    // files as they were. An exponent has at most 3 digits, so a `+` is in
    // the last 5 bytes.
    let tail = text.len().saturating_sub(5);
    match text[tail..].iter().position(|&b| b == b'+') {
        Some(k) => {
            out.extend_from_slice(&text[..tail + k]);
            out.extend_from_slice(&text[tail + k + 1..]);
        }
        None => push_short(out, text),
    }
}

/// Appends the text of one number (at most 24 bytes from `zmij`, 20 from
/// `itoa`) with fixed-size copies: `extend_from_slice` of a length known
/// only at run time calls `memcpy`, which was ~6 % of an `estimate` run.
#[inline]
fn push_short(out: &mut Vec<u8>, text: &[u8]) {
    let n = text.len();
    if !(4..=32).contains(&n) {
        out.extend_from_slice(text);
        return;
    }
    let at = out.len();
    out.extend_from_slice(&[0u8; 32]);
    let dst = &mut out[at..at + n];
    // Two overlapping copies of a fixed size cover any length in their range.
    if n >= 16 {
        dst[..16].copy_from_slice(&text[..16]);
        dst[n - 16..].copy_from_slice(&text[n - 16..]);
    } else if n >= 8 {
        dst[..8].copy_from_slice(&text[..8]);
        dst[n - 8..].copy_from_slice(&text[n - 8..]);
    } else {
        dst[..4].copy_from_slice(&text[..4]);
        dst[n - 4..].copy_from_slice(&text[n - 4..]);
    }
    out.truncate(at + n);
}

/// Writes `# key: value` lines.
pub(crate) fn write_comments<'a, W: Write>(
    w: &mut W,
    entries: impl IntoIterator<Item = (&'a str, &'a str)>,
) -> io::Result<()> {
    for (k, v) in entries {
        // A key is read back up to the first `:` of its line: one holding a
        // `:` or a line break (or none at all) would not read back as itself
        // (an audit: Python's `Trial(meta={"a\nb": ...}).write` wrote a file
        // that no reader took).
        if k.trim().is_empty() || k.contains([':', '\n', '\r']) || k.trim() != k {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!(
                    "metadata key {k:?}: expected a name without `:`, line breaks or \
                     surrounding spaces (written as `# key: value`)"
                ),
            ));
        }
        // Keep one entry on one line whatever the value holds.
        let v = v.replace(['\n', '\r'], " ");
        writeln!(w, "# {k}: {v}")?;
    }
    Ok(())
}

/// The number written in `cell` (`None` when it is not one). Accepts what
/// `str::parse::<f64>` accepts and gives the same value: `fast-float2`
/// parses the common forms, anything it refuses goes through `std`.
#[inline]
pub(crate) fn parse_number(cell: &[u8]) -> Option<f64> {
    match fast_float2::parse::<f64, _>(cell) {
        Ok(v) => Some(v),
        Err(_) => std::str::from_utf8(cell).ok()?.parse::<f64>().ok(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A metadata key that would not read back as itself is refused; a
    /// value keeps one line.
    #[test]
    fn comment_keys_must_read_back() {
        for bad in ["a\nb", "a: b", "", " a", "a\r"] {
            let mut out = Vec::new();
            let e = write_comments(&mut out, [(bad, "v")]).unwrap_err();
            assert_eq!(e.kind(), io::ErrorKind::InvalidInput, "{bad:?}");
            assert!(e.to_string().contains("metadata key"), "{e}");
        }
        let mut out = Vec::new();
        write_comments(&mut out, [("note", "two\nlines")]).unwrap();
        assert_eq!(String::from_utf8(out).unwrap(), "# note: two lines\n");
    }
    use proptest::prelude::*;

    fn written(v: f64) -> String {
        let mut out = Vec::new();
        push_value(&mut out, &mut zmij::Buffer::new(), Some(v));
        String::from_utf8(out).unwrap()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]

        /// Byte for byte the text `ryu` wrote (files stay identical), and
        /// it reads back to the same bits.
        #[test]
        fn cells_are_written_as_ryu_did_and_read_back_exactly(bits in any::<u64>()) {
            let v = f64::from_bits(bits);
            prop_assume!(v.is_finite());
            let text = written(v);
            prop_assert_eq!(&text, &ryu::Buffer::new().format_finite(v).to_string());
            prop_assert_eq!(parse_number(text.as_bytes()).map(f64::to_bits), Some(bits));
        }

        /// Integers (the fast path and around its bound), the same way.
        #[test]
        fn integers_are_written_as_ryu_did(k in -(1i64 << 53)..(1i64 << 53), shift in 0u32..12) {
            let v = (k >> shift) as f64;
            prop_assert_eq!(written(v), ryu::Buffer::new().format_finite(v).to_string());
            let w = v * 1e3;
            prop_assert_eq!(written(w), ryu::Buffer::new().format_finite(w).to_string());
        }

        /// Values of the sizes sensors and filters write, the same way.
        #[test]
        fn everyday_values_are_written_as_ryu_did(m in -1e6f64..1e6, e in -12i32..12) {
            let v = m * 10f64.powi(e);
            prop_assert_eq!(written(v), ryu::Buffer::new().format_finite(v).to_string());
        }

        /// `fast-float2` (with its `std` fallback) accepts exactly what
        /// `str::parse::<f64>` accepts, with the same value.
        #[test]
        fn parsing_agrees_with_std(s in "[-+]?[0-9]{0,20}(\\.[0-9]{0,20})?([eE][-+]?[0-9]{0,4})?") {
            let std_value = s.parse::<f64>().ok().map(f64::to_bits);
            prop_assert_eq!(parse_number(s.as_bytes()).map(f64::to_bits), std_value, "{}", s);
        }
    }

    #[test]
    fn zeros_flags_and_bounds_are_written_as_ryu_did() {
        for v in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            2.0,
            100.0,
            1e15,
            -1e15,
            1e15 - 1.0,
            1e16,
            9.5,
            -0.5,
            1e-7,
        ] {
            assert_eq!(written(v), ryu::Buffer::new().format_finite(v), "{v}");
        }
        assert_eq!(written(-0.0), "-0.0");
    }

    #[test]
    fn special_and_odd_texts_parse_as_std_does() {
        for s in [
            "", ".", "+", "-", "e5", "1e", "1e+", ".e1", "1.", ".5", "-.5", "+1", "++1", "1 ",
            " 1", "0x10", "1_0", "inf", "-inf", "+inf", "Infinity", "infinity", "INF", "nan",
            "NaN", "-nan", "in", "nana", "1e400", "1e-400", "-0", "0.0e0", "1,5", "1d5",
        ] {
            let std_value = s.parse::<f64>().ok().map(f64::to_bits);
            let ours = parse_number(s.as_bytes()).map(f64::to_bits);
            assert_eq!(ours, std_value, "{s:?}");
        }
    }
}
