//! Formatting of numeric cells: shortest round-trip decimal (ryu), so a
//! written file reads back bit for bit; a missing value is an empty cell.

use std::io::{self, Write};

/// Appends `,` and the cell for `value` to `out`.
#[inline]
pub(crate) fn push_cell(out: &mut Vec<u8>, buf: &mut ryu::Buffer, value: Option<f64>) {
    out.push(b',');
    push_value(out, buf, value);
}

/// Appends the cell for `value` (no separator).
#[inline]
pub(crate) fn push_value(out: &mut Vec<u8>, buf: &mut ryu::Buffer, value: Option<f64>) {
    if let Some(v) = value {
        if v.is_finite() {
            out.extend_from_slice(buf.format_finite(v).as_bytes());
        }
    }
}

/// Writes `# key: value` lines.
pub(crate) fn write_comments<'a, W: Write>(
    w: &mut W,
    entries: impl IntoIterator<Item = (&'a str, &'a str)>,
) -> io::Result<()> {
    for (k, v) in entries {
        // Keep one entry on one line whatever the value holds.
        let v = v.replace(['\n', '\r'], " ");
        writeln!(w, "# {k}: {v}")?;
    }
    Ok(())
}
