//! Exit statuses (SPEC section 4): 0 success, 1 user error, 2 internal error.

use std::process::ExitCode;

/// A bad file, flag or parameter.
pub const USER_ERROR: u8 = 1;
/// A bug in limbfuse.
pub const INTERNAL_ERROR: u8 = 2;

/// Marks an error as internal (a limbfuse bug), exiting with status 2.
#[derive(Debug)]
pub struct Internal(pub String);

impl std::fmt::Display for Internal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "internal error: {} (this is a limbfuse bug; please report it)",
            self.0
        )
    }
}

impl std::error::Error for Internal {}

/// Prints the error chain as one paragraph and returns its exit status.
pub fn report(e: &anyhow::Error) -> ExitCode {
    if closed_pipe(e) {
        return ExitCode::SUCCESS;
    }
    let mut msg = String::from("error: ");
    for (i, cause) in e.chain().enumerate() {
        let text = cause.to_string();
        // Typed errors often print their source already; don't repeat it.
        if i > 0 && msg.contains(&text) {
            continue;
        }
        if i > 0 {
            msg.push_str(": ");
        }
        msg.push_str(&text);
    }
    eprintln!("{msg}");
    if e.downcast_ref::<Internal>().is_some() {
        ExitCode::from(INTERNAL_ERROR)
    } else {
        ExitCode::from(USER_ERROR)
    }
}

/// Whether `e` is a write to standard output whose reader went away.
fn closed_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// Replaces Rust's panic backtrace by a short internal-error message and exit status 2.
pub fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        // arrow-rs failing on a corrupted Arrow file: limbfuse-io catches
        // the panic and reports the file as a user error.
        if limbfuse_io::arrow_file::in_guarded_read() {
            return;
        }
        let loc = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        let payload = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_default();
        // `limbfuse evaluate ... | head`: the reader closed the pipe. Not a
        // bug and not a user error: stop quietly, as Unix tools do.
        if payload.starts_with("failed printing to stdout") && payload.contains("Broken pipe") {
            std::process::exit(0);
        }
        eprintln!("internal error: {payload}{loc} (this is a limbfuse bug; please report it)");
        std::process::exit(INTERNAL_ERROR as i32);
    }));
}
