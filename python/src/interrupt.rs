//! Ctrl-C during a long run with the GIL released (`estimate`,
//! `Filter.run`): Python runs its signal handlers only when a thread holds
//! the GIL, so a loop that never takes it back ignored `KeyboardInterrupt`
//! until the whole trial was estimated (an audit: 5.5 s on a 3-hour trial
//! with `chain`, minutes on longer ones or slower methods).
//!
//! [`Interrupt::poll`] is called once per sample: every
//! [`Interrupt::STRIDE`] samples it reads the clock, and at most every
//! [`Interrupt::PERIOD`] it takes the GIL back for
//! `PyErr_CheckSignals`. Only on the main thread, the only one Python runs
//! signal handlers on: a worker thread (a threaded cohort) never takes the
//! GIL back, so it adds no contention.

use std::time::{Duration, Instant};

use pyo3::prelude::*;

/// The signal check of one run.
pub struct Interrupt {
    /// Whether the run is on Python's main thread (else it never checks).
    main: bool,
    /// Samples since the last look at the clock.
    count: u32,
    /// When the next check is due.
    next: Instant,
    /// The exception a signal handler raised (`KeyboardInterrupt`).
    raised: Option<PyErr>,
}

impl Interrupt {
    /// Samples between looks at the clock (a few microseconds of work at
    /// the fastest methods' 1 us per sample).
    pub const STRIDE: u32 = 4096;
    /// Time between signal checks: Ctrl-C stops a run within about this.
    pub const PERIOD: Duration = Duration::from_millis(100);

    /// The check of a run started by this thread (it holds the GIL).
    pub fn new(py: Python<'_>) -> PyResult<Self> {
        let threading = py.import("threading")?;
        let main = threading
            .call_method0("current_thread")?
            .is(&threading.call_method0("main_thread")?);
        Ok(Interrupt {
            main,
            count: 0,
            next: Instant::now() + Self::PERIOD,
            raised: None,
        })
    }

    /// Whether the run should stop: a signal handler raised (checked
    /// every [`Self::PERIOD`], called with the GIL released).
    #[inline]
    pub fn poll(&mut self) -> bool {
        if !self.main {
            return false;
        }
        self.count += 1;
        if self.count < Self::STRIDE {
            return false;
        }
        self.count = 0;
        self.check()
    }

    #[cold]
    fn check(&mut self) -> bool {
        let now = Instant::now();
        if now < self.next {
            return false;
        }
        self.next = now + Self::PERIOD;
        if let Err(e) = Python::attach(|py| py.check_signals()) {
            self.raised = Some(e);
            return true;
        }
        false
    }

    /// The exception a signal handler raised, if the run stopped for it.
    pub fn raised(self) -> Option<PyErr> {
        self.raised
    }
}
