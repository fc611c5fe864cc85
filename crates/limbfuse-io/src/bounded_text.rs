//! Whole small text files (parameter, calibration and gait-library files)
//! read with a bound on their size: `--params /dev/zero` read until memory
//! ran out and then said only "out of memory" (an audit); such a file is
//! now refused after `limit` bytes with what was expected.

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

/// Largest parameter or calibration file read (16 MiB): such files hold a
/// few KB of numbers, so this only stops a wrong file (a device, a
/// recording) from being read whole.
pub const MAX_SETTINGS_FILE_BYTES: u64 = 16 << 20;

/// Largest gait-library file read (1 GiB): a library of many subjects'
/// mean gait cycles is tens of MB of JSON; parsing takes a few times the
/// file's size in memory.
pub const MAX_LIBRARY_FILE_BYTES: u64 = 1 << 30;

/// `limit` in words: `16 MiB`, `1 GiB`, or bytes.
fn said(limit: u64) -> String {
    if limit >= 1 << 30 && limit.is_multiple_of(1 << 30) {
        format!("{} GiB", limit >> 30)
    } else if limit >= 1 << 20 && limit.is_multiple_of(1 << 20) {
        format!("{} MiB", limit >> 20)
    } else {
        format!("{limit} bytes")
    }
}

/// The text of the file at `path`, refused (an [`io::Error`] of kind
/// `InvalidData` saying the limit and `what` was expected) when it holds
/// more than `limit` bytes, or is not UTF-8.
pub fn read_text_at_most(path: &Path, limit: u64, what: &str) -> io::Result<String> {
    let mut bytes = Vec::new();
    File::open(path)?
        .take(limit.saturating_add(1))
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!(
                "more than {} read; expected {what} of at most {}",
                said(limit),
                said(limit)
            ),
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!(
                "not UTF-8 text (byte {}); expected {what}",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_over_the_limit_is_refused_with_what_was_expected() {
        let dir = std::env::temp_dir().join(format!("limbfuse-bounded-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("f.toml");
        std::fs::write(&p, "x = 1\n").unwrap();
        assert_eq!(read_text_at_most(&p, 6, "a file").unwrap(), "x = 1\n");
        let e = read_text_at_most(&p, 5, "a parameter file").unwrap_err();
        assert_eq!(
            e.to_string(),
            "more than 5 bytes read; expected a parameter file of at most 5 bytes"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
