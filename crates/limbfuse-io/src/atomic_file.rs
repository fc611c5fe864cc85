//! [`AtomicFile`]: an output file that appears whole or not at all.
//!
//! Every limbfuse command that writes a file writes it through this type: the
//! bytes go to a temporary file in the output's directory (so the final
//! rename stays on one file system) and [`AtomicFile::commit`] renames it over
//! the output path. Dropped without a commit (an error, a panic unwinding),
//! the temporary file is removed and an existing output file is left as it
//! was: a failed run never leaves a partial output behind.
//!
//! An output path that already exists and is not a regular file (`/dev/null`,
//! `/dev/stdout`, a named pipe) is written in place: renaming a temporary
//! file over it would replace the device with a regular file (as root,
//! `-o /dev/null` then breaks every later program that reads `/dev/null`:
//! the cause of the cargo "failed to run `rustc` to learn about
//! target-specific information" CI failures, see
//! `writing_to_a_fifo_keeps_it_a_fifo`).

use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

/// A buffered output file written under a temporary name and renamed to its
/// path only by [`AtomicFile::commit`].
#[derive(Debug)]
pub struct AtomicFile {
    path: PathBuf,
    out: Target,
}

/// Where the bytes go until [`AtomicFile::commit`].
#[derive(Debug)]
enum Target {
    /// A temporary file renamed over the output on commit.
    Temporary(BufWriter<NamedTempFile>),
    /// An existing non-regular file (device, FIFO), written in place.
    InPlace(BufWriter<std::fs::File>),
}

impl Target {
    fn writer(&mut self) -> &mut dyn WriteSeek {
        match self {
            Target::Temporary(w) => w,
            Target::InPlace(w) => w,
        }
    }
}

/// [`Write`] + [`Seek`], for [`Target::writer`].
trait WriteSeek: Write + Seek {}
impl<T: Write + Seek> WriteSeek for T {}

impl AtomicFile {
    /// Starts writing `path`: creates `.NAME.XXXXXX.tmp` in its directory.
    /// `path` itself is not touched until [`AtomicFile::commit`]. Errors are
    /// plain I/O errors: callers name `path` in their own error type.
    pub fn create(path: &Path) -> std::io::Result<Self> {
        if let Ok(meta) = std::fs::metadata(path) {
            if !meta.is_file() && !meta.is_dir() {
                let f = std::fs::OpenOptions::new().write(true).open(path)?;
                return Ok(AtomicFile {
                    path: path.to_path_buf(),
                    out: Target::InPlace(BufWriter::with_capacity(1 << 16, f)),
                });
            }
        }
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .ok_or_else(|| {
                std::io::Error::new(
                    std::io::ErrorKind::InvalidInput,
                    "expected a file name for the output, not a directory",
                )
            })?;
        let prefix = format!(".{name}.");
        let mut builder = tempfile::Builder::new();
        builder.prefix(&prefix).suffix(".tmp");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            // As `File::create`: read-write for everyone the umask allows.
            builder.permissions(std::fs::Permissions::from_mode(0o666));
        }
        // The errors name the output's folder, never the temporary file (an
        // audit: Python's `write_trial(t, "/no/such/dir/x.csv")` said
        // "No such file or directory (os error 2) at path
        // \"/no/such/dir/.x.csv.XXXXXX.tmp\"").
        if !dir.is_dir() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!("the folder {} does not exist", dir.display()),
            ));
        }
        let tmp = builder.tempfile_in(dir).map_err(|e| {
            std::io::Error::new(
                e.kind(),
                format!(
                    "cannot create a file in the folder {}: {}",
                    dir.display(),
                    e.kind()
                ),
            )
        })?;
        Ok(AtomicFile {
            path: path.to_path_buf(),
            out: Target::Temporary(BufWriter::with_capacity(1 << 16, tmp)),
        })
    }

    /// Writes `contents` to `path` atomically (the [`std::fs::write`] of this type).
    pub fn write(path: &Path, contents: impl AsRef<[u8]>) -> std::io::Result<()> {
        let mut f = Self::create(path)?;
        f.write_all(contents.as_ref())?;
        f.commit()
    }

    /// The output path (not the temporary file's).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes the data and renames the temporary file over the output path.
    /// An in-place output (device, FIFO) is only flushed.
    pub fn commit(self) -> std::io::Result<()> {
        match self.out {
            Target::Temporary(w) => {
                let tmp = w.into_inner().map_err(|e| e.into_error())?;
                tmp.persist(&self.path).map_err(|e| e.error)?;
            }
            Target::InPlace(mut w) => w.flush()?,
        }
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.out.writer().write(buf)
    }

    fn write_all(&mut self, buf: &[u8]) -> std::io::Result<()> {
        self.out.writer().write_all(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.out.writer().flush()
    }
}

impl Seek for AtomicFile {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        self.out.writer().seek(pos)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn listing(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn the_output_appears_only_on_commit() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("a.csv");
        let mut f = AtomicFile::create(&out).unwrap();
        f.write_all(b"t\n1\n").unwrap();
        f.flush().unwrap();
        assert!(!out.exists());
        f.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "t\n1\n");
        assert_eq!(listing(dir.path()), vec!["a.csv"]);
    }

    #[test]
    fn a_dropped_file_leaves_nothing_and_keeps_the_old_output() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("a.csv");
        std::fs::write(&out, "old").unwrap();
        {
            let mut f = AtomicFile::create(&out).unwrap();
            f.write_all(&vec![b'x'; 1 << 20]).unwrap();
        }
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "old");
        assert_eq!(listing(dir.path()), vec!["a.csv"]);
    }

    #[test]
    fn a_missing_directory_or_a_directory_path_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        assert!(AtomicFile::create(&dir.path().join("no/such/dir/a.csv")).is_err());
        assert!(AtomicFile::create(Path::new("/")).is_err());
    }

    /// A write into a missing folder (`/no/such/dir/x.csv`, e.g. Python's
    /// `write_trial`) named the temporary file `.x.csv.XXXXXX.tmp` as well
    /// as the target. Now the error says the folder does not exist, and no
    /// temporary name.
    #[test]
    fn a_missing_folder_is_named_without_the_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let folder = dir.path().join("no/such/dir");
        let e = AtomicFile::create(&folder.join("x.csv")).unwrap_err();
        let m = e.to_string();
        assert_eq!(e.kind(), std::io::ErrorKind::NotFound);
        assert!(
            m.contains(&format!("the folder {} does not exist", folder.display())),
            "{m}"
        );
        assert!(!m.contains(".x.csv.") && !m.contains("temporary"), "{m}");
    }

    /// Regression test for the CI runs that failed with cargo's "failed to
    /// run `rustc` to learn about target-specific information": an earlier
    /// `limbfuse ... -o /dev/null` had renamed a regular file over
    /// `/dev/null`, whose content rustc then read as source. A FIFO stands in
    /// for the device here (renaming over it is as wrong and harmless to test).
    #[cfg(unix)]
    #[test]
    fn writing_to_a_fifo_keeps_it_a_fifo() {
        use std::os::unix::fs::FileTypeExt;
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
        };
        AtomicFile::write(&fifo, "t\n1\n").unwrap();
        let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
        assert!(
            kind.is_fifo(),
            "the output path is no longer a FIFO: {kind:?}"
        );
        assert_eq!(reader.join().unwrap(), "t\n1\n");
        assert_eq!(listing(dir.path()), vec!["pipe"]);
    }
}
