//! Progress bars for the commands that can take more than a second
//! (issue 17 item 4): hidden with `--quiet` and when stderr is not a
//! terminal (indicatif draws nothing then), so piped output stays clean.

use std::sync::atomic::{AtomicBool, Ordering};

use indicatif::{ProgressBar, ProgressStyle};
use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::{Estimate, Record};

/// Whether `--quiet` was given.
static QUIET: AtomicBool = AtomicBool::new(false);

/// Records `--quiet` (called once, before any command runs).
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// A bar of `len` steps drawn with the indicatif `template`, or a hidden
/// one with `--quiet`.
pub fn bar(len: u64, template: &str) -> ProgressBar {
    if QUIET.load(Ordering::Relaxed) {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}

/// Shows the number of processed samples and the trial time reached.
pub struct Progress {
    bar: ProgressBar,
    n: u64,
}

impl Progress {
    /// A spinner labelled with `what`.
    pub fn new(what: &str) -> Self {
        let bar = if QUIET.load(Ordering::Relaxed) {
            ProgressBar::hidden()
        } else {
            ProgressBar::new_spinner()
        };
        bar.set_style(
            ProgressStyle::with_template("{spinner} {prefix} {msg} [{elapsed}]")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.set_prefix(what.to_string());
        Progress { bar, n: 0 }
    }
}

impl Observer for Progress {
    fn observe(&mut self, record: &Record, _estimate: &Estimate) -> Result<(), BoxError> {
        self.n += 1;
        if self.n.is_multiple_of(4096) {
            self.bar
                .set_message(format!("{} samples, t = {:.1} s", self.n, record.sample.t));
            self.bar.tick();
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), BoxError> {
        self.bar.finish_and_clear();
        Ok(())
    }
}
