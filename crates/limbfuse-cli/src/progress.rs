//! A progress observer for long runs (hidden when stderr is not a terminal).

use indicatif::{ProgressBar, ProgressStyle};
use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::{Estimate, Record};

/// Shows the number of processed samples and the trial time reached.
pub struct Progress {
    bar: ProgressBar,
    n: u64,
}

impl Progress {
    /// A spinner labelled with `what`.
    pub fn new(what: &str) -> Self {
        let bar = ProgressBar::new_spinner();
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
