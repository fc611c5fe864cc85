//! Byte-level CSV splitting for [`crate::table::TableReader`]: lines are
//! found with `memchr` in one reusable buffer (or in the mapped file,
//! [`LineSource::mapped`]) and split into cell bounds in place, so reading
//! a row copies and allocates nothing.
//!
//! Quoting (RFC 4180 as the `csv` crate reads it) is handled on a slower
//! path, taken only by lines that hold a `"`: a cell that starts with `"`
//! runs to the matching `"` (`""` is a literal quote, a line break inside
//! continues the cell on the next line), bytes after the closing quote are
//! kept. Every cell is trimmed of ASCII white space (so `\r\n` line ends
//! read like `\n`).

use std::io::{self, Read};
use std::ops::Range;

use memchr::memchr;

use crate::content_hash::HashHandle;
use crate::mapped_file::MappedFile;

/// Longest line accepted: a bound on the memory one row may take (a file
/// without line breaks is not read whole into memory).
pub(crate) const MAX_LINE_BYTES: usize = 64 << 20;

/// Bytes of a mapped file hashed at a time, as the lines pass (while
/// they are still in the cache).
const HASH_STEP: usize = 256 << 10;

/// Reads lines from a byte source into one growing buffer, or from a
/// mapped file in place.
pub(crate) struct LineSource {
    source: Box<dyn Read + Send>,
    buf: Vec<u8>,
    /// The mapped file (then `buf` is unused and `end` is its length), its
    /// hash, and how far it has been hashed.
    map: Option<(MappedFile, HashHandle, usize)>,
    start: usize,
    end: usize,
    at_end: bool,
    /// The line last returned ended the source without a `\n`.
    unterminated: bool,
}

/// Why a line could not be read.
pub(crate) enum LineError {
    /// The source failed.
    Io(io::Error),
    /// A line longer than [`MAX_LINE_BYTES`].
    TooLong,
}

impl LineSource {
    /// Reads `source` in blocks of 256 KiB (a line may grow the buffer).
    pub(crate) fn new(source: Box<dyn Read + Send>) -> Self {
        LineSource {
            source,
            buf: vec![0; 256 << 10],
            map: None,
            start: 0,
            end: 0,
            at_end: false,
            unterminated: false,
        }
    }

    /// Reads the lines of a mapped file in place; `hash` receives its
    /// bytes as the lines pass, and is finished at the end.
    pub(crate) fn mapped(map: MappedFile, hash: HashHandle) -> Self {
        LineSource {
            source: Box::new(io::empty()),
            buf: Vec::new(),
            end: map.bytes().len(),
            map: Some((map, hash, 0)),
            start: 0,
            at_end: true,
            unterminated: false,
        }
    }

    /// A source with no lines (for a table that is not CSV).
    pub(crate) fn none() -> Self {
        LineSource {
            source: Box::new(io::empty()),
            buf: Vec::new(),
            map: None,
            start: 0,
            end: 0,
            at_end: true,
            unterminated: false,
        }
    }

    /// The bytes read: the buffer, or the whole mapped file.
    #[inline]
    fn data(&self) -> &[u8] {
        match &self.map {
            Some((map, _, _)) => map.bytes(),
            None => &self.buf,
        }
    }

    /// The bytes of a line returned by [`LineSource::next_line`], valid
    /// until the next call.
    #[inline]
    pub(crate) fn bytes(&self, line: Range<usize>) -> &[u8] {
        &self.data()[line]
    }

    /// Skips a UTF-8 byte-order mark (`EF BB BF`) at the very start of the
    /// source: spreadsheet programs and Windows tools write one before the
    /// first line of a CSV, and it would otherwise become part of the first
    /// comment's `#` or of the first column's name. Call before the first line.
    pub(crate) fn skip_byte_order_mark(&mut self) -> Result<(), LineError> {
        const BOM: [u8; 3] = [0xEF, 0xBB, 0xBF];
        while self.end - self.start < BOM.len() && !self.at_end {
            self.fill()?;
        }
        if self.data()[self.start..self.end].starts_with(&BOM) {
            self.start += BOM.len();
        }
        Ok(())
    }

    /// The line last returned was the source's last and had no `\n`: a
    /// file whose writer stopped in the middle of a line, if it is short.
    pub(crate) fn last_line_unterminated(&self) -> bool {
        self.unterminated
    }

    /// The first byte of the next line, without consuming it (`None` at the end).
    pub(crate) fn peek(&mut self) -> Result<Option<u8>, LineError> {
        while self.start == self.end && !self.at_end {
            self.fill()?;
        }
        Ok((self.start < self.end).then(|| self.data()[self.start]))
    }

    /// The next line of a mapped file (as [`LineSource::next_line`]),
    /// hashing the bytes passed.
    fn next_mapped_line(&mut self) -> Result<Option<Range<usize>>, LineError> {
        let Some((map, hash, hashed)) = &mut self.map else {
            return Ok(None);
        };
        let bytes = map.bytes();
        if *hashed + HASH_STEP <= self.start || self.start == self.end {
            hash.update(&bytes[*hashed..self.start]);
            *hashed = self.start;
            if self.start == self.end {
                hash.finish_input();
                return Ok(None);
            }
        }
        // A line is at most MAX_LINE_BYTES long, as when streamed.
        let scan_end = self.end.min(self.start + MAX_LINE_BYTES);
        let line_end = match memchr(b'\n', &bytes[self.start..scan_end]) {
            Some(i) => self.start + i,
            None if scan_end == self.end && self.end - self.start < MAX_LINE_BYTES => {
                self.unterminated = true;
                self.end
            }
            None => return Err(LineError::TooLong),
        };
        let line = self.start..line_end;
        self.start = (line_end + 1).min(self.end);
        Ok(Some(line))
    }

    /// The next line without its `\n` (as a range of [`LineSource::bytes`]);
    /// `None` at the end. Returns as soon as the line's `\n` has arrived (a
    /// pipe is not waited on to fill the buffer).
    pub(crate) fn next_line(&mut self) -> Result<Option<Range<usize>>, LineError> {
        if self.map.is_some() {
            return self.next_mapped_line();
        }
        let mut scan_from = self.start;
        loop {
            if let Some(i) = memchr(b'\n', &self.buf[scan_from..self.end]) {
                let line = self.start..scan_from + i;
                self.start = scan_from + i + 1;
                return Ok(Some(line));
            }
            if self.at_end {
                if self.start == self.end {
                    return Ok(None);
                }
                let line = self.start..self.end;
                self.start = self.end;
                self.unterminated = true;
                return Ok(Some(line));
            }
            let scanned = self.end - self.start;
            self.fill()?;
            scan_from = self.start + scanned;
        }
    }

    /// Moves the unread bytes to the front, grows the buffer if it is full,
    /// and reads once more.
    fn fill(&mut self) -> Result<(), LineError> {
        if self.start > 0 {
            self.buf.copy_within(self.start..self.end, 0);
            self.end -= self.start;
            self.start = 0;
        }
        if self.end == self.buf.len() {
            if self.buf.len() >= MAX_LINE_BYTES {
                return Err(LineError::TooLong);
            }
            self.buf.resize((self.buf.len() * 2).min(MAX_LINE_BYTES), 0);
        }
        loop {
            match self.source.read(&mut self.buf[self.end..]) {
                Ok(0) => {
                    self.at_end = true;
                    return Ok(());
                }
                Ok(n) => {
                    self.end += n;
                    return Ok(());
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(LineError::Io(e)),
            }
        }
    }
}

/// Trims ASCII white space from both ends of `bytes[range]`.
#[inline]
fn trimmed(bytes: &[u8], mut start: usize, mut end: usize) -> (u32, u32) {
    while start < end && bytes[start].is_ascii_whitespace() {
        start += 1;
    }
    while end > start && bytes[end - 1].is_ascii_whitespace() {
        end -= 1;
    }
    (start as u32, end as u32)
}

/// True when the cells are one empty cell (a blank line, skipped).
pub(crate) fn is_blank(cells: &[(u32, u32)]) -> bool {
    matches!(cells, [(a, b)] if a == b)
}

/// Splits a line at its commas into trimmed cell bounds; returns false
/// (cells unspecified) when the line holds a `"`: it needs [`split_quoted`].
///
/// The line is scanned 32 bytes at a time into bit masks of its commas and
/// quotes ([`separator_masks`]), so a cell costs a few instructions, not a
/// search call (`memchr2` per cell was ~7 % of an `estimate` run).
#[inline]
pub(crate) fn split_plain(line: &[u8], cells: &mut Vec<(u32, u32)>) -> bool {
    cells.clear();
    let mut start = 0;
    let mut base = 0;
    let mut blocks = line.chunks_exact(BLOCK);
    for block in blocks.by_ref() {
        let block: &[u8; BLOCK] = block.try_into().unwrap_or(&[0; BLOCK]);
        let (commas, quotes) = separator_masks(block);
        if quotes != 0 {
            return false;
        }
        start = push_cells(line, base, commas, start, cells);
        base += BLOCK;
    }
    let rest = blocks.remainder();
    if !rest.is_empty() {
        // Zero padding holds no comma and no quote.
        let mut block = [0u8; BLOCK];
        block[..rest.len()].copy_from_slice(rest);
        let (commas, quotes) = separator_masks(&block);
        if quotes != 0 {
            return false;
        }
        start = push_cells(line, base, commas, start, cells);
    }
    cells.push(trimmed(line, start, line.len()));
    true
}

/// Bytes scanned at once by [`split_plain`].
const BLOCK: usize = 32;

/// Pushes the cell ending at each comma of `commas` (bit `i`: a comma at
/// `base + i`); returns where the next cell starts.
#[inline]
fn push_cells(
    line: &[u8],
    base: usize,
    mut commas: u32,
    mut start: usize,
    cells: &mut Vec<(u32, u32)>,
) -> usize {
    while commas != 0 {
        let at = base + commas.trailing_zeros() as usize;
        cells.push(trimmed(line, start, at));
        start = at + 1;
        commas &= commas - 1;
    }
    start
}

/// Bit masks of the commas and of the quotes in `block` (bit `i` for byte `i`).
#[cfg(target_arch = "x86_64")]
#[inline]
fn separator_masks(block: &[u8; BLOCK]) -> (u32, u32) {
    use std::arch::x86_64::{
        __m128i, _mm_cmpeq_epi8, _mm_loadu_si128, _mm_movemask_epi8, _mm_set1_epi8,
    };
    // SAFETY: SSE2 is part of every x86-64 CPU (the target's baseline), and
    // both unaligned loads read 16 bytes inside the 32-byte array.
    unsafe {
        let lo = _mm_loadu_si128(block.as_ptr().cast::<__m128i>());
        let hi = _mm_loadu_si128(block.as_ptr().add(16).cast::<__m128i>());
        let comma = _mm_set1_epi8(b',' as i8);
        let quote = _mm_set1_epi8(b'"' as i8);
        let mask = |v, c| _mm_movemask_epi8(_mm_cmpeq_epi8(v, c)) as u32 & 0xFFFF;
        (
            mask(lo, comma) | (mask(hi, comma) << 16),
            mask(lo, quote) | (mask(hi, quote) << 16),
        )
    }
}

/// Bit masks of the commas and of the quotes in `block` (bit `i` for byte `i`).
#[cfg(not(target_arch = "x86_64"))]
#[inline]
fn separator_masks(block: &[u8; BLOCK]) -> (u32, u32) {
    let (mut commas, mut quotes) = (0u32, 0u32);
    for (i, &b) in block.iter().enumerate() {
        commas |= u32::from(b == b',') << i;
        quotes |= u32::from(b == b'"') << i;
    }
    (commas, quotes)
}

/// Splits a record that may hold quoted cells, writing the cell texts
/// (quotes removed, `""` as `"`) to `text` and their bounds to `cells`.
/// Returns false when a quoted cell is still open at the end of `record`
/// (its next line belongs to it).
pub(crate) fn split_quoted(record: &[u8], text: &mut Vec<u8>, cells: &mut Vec<(u32, u32)>) -> bool {
    text.clear();
    cells.clear();
    let mut i = 0;
    loop {
        let cell_start = text.len();
        if record.get(i) == Some(&b'"') {
            i += 1;
            loop {
                match record.get(i) {
                    None => return false,
                    Some(b'"') if record.get(i + 1) == Some(&b'"') => {
                        text.push(b'"');
                        i += 2;
                    }
                    Some(b'"') => {
                        i += 1;
                        break;
                    }
                    Some(&b) => {
                        text.push(b);
                        i += 1;
                    }
                }
            }
        }
        let rest = &record[i..];
        let stop = memchr(b',', rest).unwrap_or(rest.len());
        text.extend_from_slice(&rest[..stop]);
        i += stop;
        cells.push(trimmed(text, cell_start, text.len()));
        if i >= record.len() {
            return true;
        }
        i += 1; // the comma
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plain(line: &str) -> Vec<String> {
        let mut cells = Vec::new();
        assert!(split_plain(line.as_bytes(), &mut cells));
        cells
            .iter()
            .map(|&(a, b)| line[a as usize..b as usize].to_string())
            .collect()
    }

    fn quoted(record: &str) -> Option<Vec<String>> {
        let (mut text, mut cells) = (Vec::new(), Vec::new());
        split_quoted(record.as_bytes(), &mut text, &mut cells).then(|| {
            cells
                .iter()
                .map(|&(a, b)| String::from_utf8(text[a as usize..b as usize].to_vec()).unwrap())
                .collect()
        })
    }

    #[test]
    fn plain_lines_split_at_commas_and_trim() {
        assert_eq!(plain("t, a ,b\r"), ["t", "a", "b"]);
        assert_eq!(plain(",,"), ["", "", ""]);
        assert_eq!(plain(""), [""]);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(5_000))]

        /// Lines of any length (across the 32-byte blocks and their tail):
        /// the same cells as splitting at every comma and trimming; a line
        /// with a quote anywhere is handed to the quoted path.
        #[test]
        fn block_scan_splits_as_a_plain_split_does(line in "[a1, \\t\"\\.]{0,100}") {
            let mut cells = Vec::new();
            let plain = split_plain(line.as_bytes(), &mut cells);
            proptest::prop_assert_eq!(plain, !line.contains('"'));
            if plain {
                let got: Vec<&str> = cells
                    .iter()
                    .map(|&(a, b)| &line[a as usize..b as usize])
                    .collect();
                let want: Vec<&str> = line
                    .split(',')
                    .map(|c| c.trim_matches(|ch: char| ch.is_ascii_whitespace()))
                    .collect();
                proptest::prop_assert_eq!(got, want);
            }
        }
    }

    #[test]
    fn quoted_cells_keep_commas_and_escaped_quotes() {
        assert_eq!(
            quoted(r#"1,"a,b","say ""hi""",x"#).unwrap(),
            ["1", "a,b", r#"say "hi""#, "x"]
        );
        assert_eq!(quoted(r#""x"y,2"#).unwrap(), ["xy", "2"]);
        assert_eq!(quoted("\"open,1"), None);
        assert_eq!(quoted("\"two\nlines\",1").unwrap(), ["two\nlines", "1"]);
    }

    /// The splitter agrees with the `csv` crate (as the reader used it
    /// before: flexible, trimmed) on every line of a mixed sample.
    #[test]
    fn agrees_with_the_csv_crate() {
        let lines = [
            "t,thigh_gyr_x,knee_enc",
            " 0.5 ,  -1e-3,\t2 ",
            ",,",
            "a,\"b,c\",d",
            "\"\"\"q\"\"\",x",
            "1.0,,3\r",
            "x",
        ];
        for line in lines {
            let mut r = csv::ReaderBuilder::new()
                .has_headers(false)
                .flexible(true)
                .trim(csv::Trim::All)
                .from_reader(line.as_bytes());
            let mut rec = csv::ByteRecord::new();
            assert!(r.read_byte_record(&mut rec).unwrap());
            let want: Vec<String> = rec
                .iter()
                .map(|c| String::from_utf8(c.to_vec()).unwrap())
                .collect();
            let got = if line.contains('"') {
                assert!(!split_plain(line.as_bytes(), &mut Vec::new()));
                quoted(line).unwrap()
            } else {
                plain(line)
            };
            assert_eq!(got, want, "{line:?}");
        }
    }

    #[test]
    fn lines_are_found_across_reads_of_any_size() {
        /// Gives out its bytes a few at a time, as a pipe does.
        struct Trickle(Vec<u8>, usize);
        impl Read for Trickle {
            fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
                let n = buf.len().min(3).min(self.0.len() - self.1);
                buf[..n].copy_from_slice(&self.0[self.1..self.1 + n]);
                self.1 += n;
                Ok(n)
            }
        }
        let text = "ab\n\ncdef\r\nlast";
        let mut src = LineSource::new(Box::new(Trickle(text.as_bytes().to_vec(), 0)));
        let mut got = Vec::new();
        while let Ok(Some(r)) = src.next_line() {
            got.push(String::from_utf8(src.bytes(r).to_vec()).unwrap());
        }
        assert_eq!(got, ["ab", "", "cdef\r", "last"]);
    }
}
