//! Which trial an estimate file came from: the trial file's content hash
//! (XXH3-64 of its bytes, `xxhash-rust`), written in the estimate file's
//! header (`# trial:` and `# trial_hash:`, see docs/OUTPUTS.md) and
//! checked by `limbfuse evaluate`.
//!
//! [`HashingReader`] hashes the bytes as a reader streams them, so
//! `estimate` hashes its trial without reading it twice;
//! [`TrialFingerprint::of_file`] hashes a file in one pass and counts its
//! data rows (for `evaluate`, which checks both before evaluating).

use std::fmt;
use std::io::Read;
use std::path::Path;
use std::sync::{Arc, Mutex};

use xxhash_rust::xxh3::Xxh3;

use crate::error::FileError;

/// Estimate-file metadata key of the trial's file name.
pub const TRIAL_KEY: &str = "trial";
/// Estimate-file metadata key of the trial's [`ContentHash`].
pub const TRIAL_HASH_KEY: &str = "trial_hash";
/// The `# trial_hash:` value of an estimate streamed as it was made (to
/// standard output): its header was written before the trial's end, so the
/// hash was not known (docs/STREAMING.md).
pub const STREAMED_HASH: &str = "streamed";

/// The XXH3-64 hash of a file's bytes; written `xxh3:` + 16 hex digits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ContentHash(pub u64);

impl ContentHash {
    /// Length of the written form (`xxh3:` + 16 hex digits).
    pub const TEXT_LEN: usize = 5 + 16;

    /// The hash of `bytes`.
    pub fn of_bytes(bytes: &[u8]) -> Self {
        ContentHash(xxhash_rust::xxh3::xxh3_64(bytes))
    }

    /// Parses the written form `xxh3:0123456789abcdef`.
    pub fn parse(text: &str) -> Option<Self> {
        let hex = text.trim().strip_prefix("xxh3:")?;
        if hex.len() != 16 {
            return None;
        }
        u64::from_str_radix(hex, 16).ok().map(ContentHash)
    }
}

impl fmt::Display for ContentHash {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "xxh3:{:016x}", self.0)
    }
}

/// The running hash shared between a [`HashingReader`] and its owner.
#[derive(Clone, Default)]
pub struct HashHandle(Arc<Mutex<HashState>>);

#[derive(Default)]
struct HashState {
    hasher: Xxh3,
    at_end: bool,
}

impl fmt::Debug for HashHandle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("HashHandle")
    }
}

impl HashHandle {
    /// The hash of every byte read, once the reader has reached the end of
    /// its source; `None` before (a partial hash identifies nothing).
    pub fn finished(&self) -> Option<ContentHash> {
        let s = self.0.lock().ok()?;
        s.at_end.then(|| ContentHash(s.hasher.digest()))
    }

    /// Hashes the next bytes of the source (read in place, not through a
    /// [`HashingReader`]).
    pub(crate) fn update(&self, bytes: &[u8]) {
        if let Ok(mut s) = self.0.lock() {
            s.hasher.update(bytes);
        }
    }

    /// Marks the source as read to its end: [`HashHandle::finished`] gives the hash.
    pub(crate) fn finish_input(&self) {
        if let Ok(mut s) = self.0.lock() {
            s.at_end = true;
        }
    }
}

/// A reader that hashes the bytes passing through it.
pub struct HashingReader<R> {
    inner: R,
    state: HashHandle,
}

impl<R: Read> HashingReader<R> {
    /// Wraps `inner`; the returned handle gives the hash at the end.
    pub fn new(inner: R) -> (Self, HashHandle) {
        let state = HashHandle::default();
        (
            HashingReader {
                inner,
                state: state.clone(),
            },
            state,
        )
    }
}

impl<R: Read> Read for HashingReader<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        if let Ok(mut s) = self.state.0.lock() {
            if n == 0 && !buf.is_empty() {
                s.at_end = true;
            } else {
                s.hasher.update(&buf[..n]);
            }
        }
        Ok(n)
    }
}

/// The [`ContentHash`] of the file at `path` (read once, in blocks).
pub fn of_file(path: &Path) -> Result<ContentHash, FileError> {
    let mut file = std::fs::File::open(path).map_err(|e| FileError::io(path, e))?;
    let mut hasher = Xxh3::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        match file.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => hasher.update(&buf[..n]),
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(FileError::io(path, e)),
        }
    }
    Ok(ContentHash(hasher.digest()))
}

/// A file's content hash and the number of data rows of the limbfuse table
/// it holds, from one pass over its bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TrialFingerprint {
    /// Hash of the file's bytes.
    pub hash: ContentHash,
    /// Lines after the leading `#` comment lines and the header row (blank
    /// lines included, so an upper bound on the samples; exact for files
    /// limbfuse writes).
    pub data_rows: u64,
}

impl TrialFingerprint {
    /// Reads `path` once (an Arrow file, [`crate::arrow_file::is_arrow_path`]:
    /// hashes its bytes and counts the rows of its batches).
    pub fn of_file(path: &Path) -> Result<Self, FileError> {
        if crate::arrow_file::is_arrow_path(path) {
            let (hash, data_rows) = crate::arrow_source::hash_and_rows(path)?;
            return Ok(TrialFingerprint { hash, data_rows });
        }
        let mut file = std::fs::File::open(path).map_err(|e| FileError::io(path, e))?;
        Self::of_reader(&mut file).map_err(|e| FileError::io(path, e))
    }

    /// Reads `source` to its end.
    pub fn of_reader(source: &mut dyn Read) -> std::io::Result<Self> {
        let mut hasher = Xxh3::new();
        let mut buf = vec![0u8; 1 << 16];
        // Lines ended so far, and whether the current line has bytes.
        let mut lines = 0u64;
        let mut open_line = false;
        // Leading comment lines (`#` at a line start before any other line).
        let mut preamble = 0u64;
        let mut in_preamble = true;
        loop {
            let n = match source.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            let chunk = &buf[..n];
            hasher.update(chunk);
            let mut rest = chunk;
            while in_preamble && !rest.is_empty() {
                // At a line start unless a line is open.
                if !open_line && rest[0] != b'#' {
                    in_preamble = false;
                    break;
                }
                match rest.iter().position(|&b| b == b'\n') {
                    Some(i) => {
                        if !open_line {
                            preamble += 1;
                        }
                        lines += 1;
                        open_line = false;
                        rest = &rest[i + 1..];
                    }
                    None => {
                        if !open_line {
                            preamble += 1;
                        }
                        open_line = true;
                        rest = &[];
                    }
                }
            }
            let newlines = rest.iter().filter(|&&b| b == b'\n').count() as u64;
            lines += newlines;
            if let Some(&last) = rest.last() {
                open_line = last != b'\n';
            }
        }
        if open_line {
            lines += 1;
        }
        let data_rows = lines.saturating_sub(preamble).saturating_sub(1);
        Ok(TrialFingerprint {
            hash: ContentHash(hasher.digest()),
            data_rows,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_written_form_round_trips() {
        let h = ContentHash(0x0123_4567_89ab_cdef);
        assert_eq!(h.to_string(), "xxh3:0123456789abcdef");
        assert_eq!(h.to_string().len(), ContentHash::TEXT_LEN);
        assert_eq!(ContentHash::parse(&h.to_string()), Some(h));
        assert_eq!(ContentHash::parse("xxh3:12"), None);
        assert_eq!(ContentHash::parse("md5:0123456789abcdef"), None);
    }

    #[test]
    fn streaming_and_one_pass_hashes_agree_and_rows_are_counted() {
        let text = "# format: x\n# g: 9.81\nt,a\n0,1\n0.1,2\n0.2,3";
        let (mut r, handle) = HashingReader::new(text.as_bytes());
        assert_eq!(handle.finished(), None);
        let mut sink = Vec::new();
        // Small reads, as a buffered reader may do.
        let mut buf = [0u8; 5];
        loop {
            let n = r.read(&mut buf).unwrap();
            if n == 0 {
                break;
            }
            sink.extend_from_slice(&buf[..n]);
        }
        let fp = TrialFingerprint::of_reader(&mut text.as_bytes()).unwrap();
        assert_eq!(handle.finished(), Some(fp.hash));
        assert_eq!(fp.hash, ContentHash::of_bytes(text.as_bytes()));
        assert_eq!(fp.data_rows, 3);
        let with_newline = format!("{text}\n");
        let fp2 = TrialFingerprint::of_reader(&mut with_newline.as_bytes()).unwrap();
        assert_eq!(fp2.data_rows, 3);
        assert_ne!(fp2.hash, fp.hash);
        let no_comments = TrialFingerprint::of_reader(&mut "t\n1\n2\n".as_bytes()).unwrap();
        assert_eq!(no_comments.data_rows, 2);
    }
}
