//! A trial file's bytes in place: mapped read-only into memory (`mmap`), so
//! that the readers take its lines and Arrow batches straight from the page
//! cache instead of copying them through `read` into buffers of their own
//! (issue 18 item 6: the copy, and for Arrow the zeroed buffer of every
//! batch and its page faults, were ~10 % of an Arrow `estimate`).
//!
//! Only a regular, non-empty file on a Unix system is mapped; anything else
//! (a pipe, a device, an empty file, a failed `mmap`) gives `None` and the
//! reader streams it as before. The mapping is private and read-only; the
//! kernel is told the file is read sequentially, so it reads ahead and may
//! drop pages already passed (they are the page cache's, not the process's
//! heap: memory use stays that of one row or batch).
//!
//! A file truncated by another process while it is mapped makes the reader
//! fault (`SIGBUS`) on the missing pages, as any `mmap` reader does; a file
//! rewritten in place shows its new bytes. Neither is bad input in the
//! sense of this crate's errors (the file is changed under the reader).

use std::fs::File;
use std::ptr::NonNull;

/// A file mapped read-only into memory; unmapped on drop.
pub(crate) struct MappedFile {
    ptr: NonNull<u8>,
    len: usize,
}

// The mapping is read-only and owned: sharing or sending it is sharing a `&[u8]`.
unsafe impl Send for MappedFile {}
unsafe impl Sync for MappedFile {}

impl std::fmt::Debug for MappedFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MappedFile")
            .field("len", &self.len)
            .finish()
    }
}

impl MappedFile {
    /// Maps `file` when it is a regular, non-empty file; `None` otherwise
    /// (the caller reads it as a stream).
    #[cfg(unix)]
    pub(crate) fn map(file: &File) -> Option<Self> {
        use std::os::unix::io::AsRawFd;
        let meta = file.metadata().ok()?;
        if !meta.is_file() || meta.len() == 0 {
            return None;
        }
        let len = usize::try_from(meta.len()).ok()?;
        // SAFETY: a fresh private read-only mapping of an open file
        // descriptor; the result is checked before use, and the mapping
        // stays valid after the descriptor is closed.
        let ptr = unsafe {
            libc::mmap(
                std::ptr::null_mut(),
                len,
                libc::PROT_READ,
                libc::MAP_PRIVATE,
                file.as_raw_fd(),
                0,
            )
        };
        if ptr == libc::MAP_FAILED {
            return None;
        }
        // SAFETY: `ptr..ptr + len` is the mapping made above. Advice only:
        // its failure changes nothing but speed.
        unsafe {
            libc::madvise(ptr, len, libc::MADV_SEQUENTIAL);
        }
        Some(MappedFile {
            ptr: NonNull::new(ptr.cast())?,
            len,
        })
    }

    /// Not mapped on this platform: the caller reads the file as a stream.
    #[cfg(not(unix))]
    pub(crate) fn map(_file: &File) -> Option<Self> {
        None
    }

    /// The file's bytes.
    #[inline]
    pub(crate) fn bytes(&self) -> &[u8] {
        // SAFETY: `ptr` maps `len` readable bytes until `self` is dropped.
        unsafe { std::slice::from_raw_parts(self.ptr.as_ptr(), self.len) }
    }

    /// The start of the mapping (page-aligned), for a zero-copy Arrow buffer.
    pub(crate) fn ptr(&self) -> NonNull<u8> {
        self.ptr
    }
}

impl Drop for MappedFile {
    fn drop(&mut self) {
        #[cfg(unix)]
        // SAFETY: unmaps the mapping made in `map`, which nothing borrows
        // any more (`bytes` borrows `self`).
        unsafe {
            libc::munmap(self.ptr.as_ptr().cast(), self.len);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn a_regular_file_maps_to_its_bytes_and_an_empty_one_does_not_map() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.csv");
        let text: Vec<u8> = (0..100_000u32).flat_map(|k| k.to_le_bytes()).collect();
        std::fs::File::create(&path)
            .unwrap()
            .write_all(&text)
            .unwrap();
        let m = MappedFile::map(&File::open(&path).unwrap());
        if cfg!(unix) {
            assert_eq!(m.unwrap().bytes(), &text[..]);
        }
        let empty = dir.path().join("e.csv");
        std::fs::write(&empty, b"").unwrap();
        assert!(MappedFile::map(&File::open(&empty).unwrap()).is_none());
    }
}
