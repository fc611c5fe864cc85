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
//!
//! The other long calls (`simulate`, `align`, `report`, `inspect`,
//! `gait_library`, the IMM library extension, reading and writing files,
//! ...; audits, sessions 29 and 30: none stopped before its end) run in
//! [`detach`], which installs the
//! run's check for this thread: loops of this crate call [`poll_current`]
//! per sample, and the workspace crates' searches get [`cancelled`] as
//! their cancellation hook (`SearchSettings::cancel`, `AlignOptions::cancel`,
//! `ReportInput::cancel`: a plain `fn`, so the
//! no_std-minded crates see no Python and no signal).

use std::cell::RefCell;
use std::time::{Duration, Instant};

use pyo3::marker::Ungil;
use pyo3::prelude::*;

thread_local! {
    /// The check of the run [`detach`] runs on this thread.
    static CURRENT: RefCell<Option<Interrupt>> = const { RefCell::new(None) };
}

/// Runs `f` with the GIL released, as `py.detach`, with a check of Ctrl-C
/// that [`poll_current`] and [`cancelled`] consult; the exception a signal
/// handler raised when they stopped it (`KeyboardInterrupt`), else `f`'s
/// result. (A run started from inside a signal handler of a run, or from
/// another thread, runs unchecked.)
pub fn detach<T: Ungil>(py: Python<'_>, f: impl FnOnce() -> T + Ungil) -> PyResult<T> {
    let mine = Interrupt::new(py)?;
    let installed = CURRENT.with(|c| match c.try_borrow_mut() {
        Ok(mut slot) if slot.is_none() => {
            *slot = Some(mine);
            true
        }
        _ => false,
    });
    let out = py.detach(f);
    if !installed {
        return Ok(out);
    }
    let mine = CURRENT.with(|c| c.borrow_mut().take());
    match mine.and_then(Interrupt::raised) {
        Some(e) => Err(e),
        None => Ok(out),
    }
}

/// Per sample in a loop run by [`detach`]: whether to stop (strided as
/// [`Interrupt::poll`]: a few nanoseconds).
#[inline]
pub fn poll_current() -> bool {
    CURRENT.with(|c| {
        c.try_borrow_mut()
            .is_ok_and(|mut i| i.as_mut().is_some_and(Interrupt::poll))
    })
}

/// The cancellation hook of a coarse step (a simulated B-SLIP step, a
/// pass over a trial) in a run of [`detach`]: reads the clock every call.
pub fn cancelled() -> bool {
    CURRENT.with(|c| {
        c.try_borrow_mut()
            .is_ok_and(|mut i| i.as_mut().is_some_and(Interrupt::due))
    })
}

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

    /// Whether the run should stop, looking at the clock now (for coarse
    /// steps); stays true once a handler raised.
    pub fn due(&mut self) -> bool {
        self.main && self.check()
    }

    #[cold]
    fn check(&mut self) -> bool {
        if self.raised.is_some() {
            return true;
        }
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
