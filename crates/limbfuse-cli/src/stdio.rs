//! `-` as a file name: a trial read from standard input and an estimate
//! written to standard output as its rows arrive (issue 18 item 5,
//! docs/STREAMING.md).
//!
//! Output is buffered, and flushed whenever the input is about to wait for
//! more bytes: a burst of rows (a file piped in) costs one write per
//! 256 KiB read, and a live source that sends one row at a time gets each
//! estimate as soon as its row has been processed.

use std::io::{self, BufWriter, Read, Stdout, Write};
use std::path::Path;
use std::sync::{Arc, Mutex};

/// The file name that means standard input or output.
pub const STDIO_NAME: &str = "-";

/// The name used for standard input in messages and in `# trial:`.
pub const STDIN_LABEL: &str = "<stdin>";

/// True when `path` is `-`.
pub fn is_stdio(path: &Path) -> bool {
    path.as_os_str() == STDIO_NAME
}

/// Buffered standard output, shared by the estimate writer and by the
/// input that flushes it ([`FlushingStdin`]).
#[derive(Clone)]
pub struct SharedStdout(Arc<Mutex<BufWriter<Stdout>>>);

impl SharedStdout {
    /// Standard output behind a 64 KiB buffer.
    pub fn new() -> Self {
        SharedStdout(Arc::new(Mutex::new(BufWriter::with_capacity(
            64 << 10,
            io::stdout(),
        ))))
    }

    fn with<T>(&self, f: impl FnOnce(&mut BufWriter<Stdout>) -> io::Result<T>) -> io::Result<T> {
        let mut out = self
            .0
            .lock()
            .map_err(|_| io::Error::other("standard output: a writer panicked"))?;
        f(&mut out)
    }
}

impl Write for SharedStdout {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.with(|o| o.write(buf))
    }
    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        self.with(|o| o.write_all(buf))
    }
    fn flush(&mut self) -> io::Result<()> {
        self.with(|o| o.flush())
    }
}

/// Standard input that flushes `output` (if any) before each read, so that
/// every estimate made from the rows read so far is out before the input
/// waits.
pub struct FlushingStdin {
    input: io::Stdin,
    output: Option<SharedStdout>,
}

impl FlushingStdin {
    /// Standard input; flushes `output` before each read.
    pub fn new(output: Option<SharedStdout>) -> Self {
        FlushingStdin {
            input: io::stdin(),
            output,
        }
    }
}

impl Read for FlushingStdin {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if let Some(out) = &mut self.output {
            out.flush()?;
        }
        self.input.read(buf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_lone_dash_is_standard_io() {
        assert!(is_stdio(Path::new("-")));
        assert!(!is_stdio(Path::new("./-")));
        assert!(!is_stdio(Path::new("-.csv")));
    }
}
