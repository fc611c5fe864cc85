//! Stopping work that runs on rayon's pool from a check that can only be
//! made on the calling thread (the Python binding's Ctrl-C check reads
//! that thread's state and takes the GIL there). The work runs in a scoped
//! thread; the calling thread asks `cancel` about every
//! [`POLL_PERIOD`] and raises a flag the work reads between its own steps.
//! Used by `monte_carlo` (runs) and `fes_torque_tuning` (candidates).

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// How often the calling thread asks `cancel`.
pub const POLL_PERIOD: Duration = Duration::from_millis(50);

/// The flag the work reads: raised once `cancel` said stop.
#[derive(Debug, Default)]
pub struct StopFlag(AtomicBool);

impl StopFlag {
    /// Whether the work should stop.
    #[inline]
    pub fn raised(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    fn raise(&self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

/// Runs `work` with a [`StopFlag`]: without `cancel` on this thread (the
/// flag is never raised); with it, in a scoped thread while this thread
/// asks `cancel` every [`POLL_PERIOD`] (woken as soon as `work` returns,
/// so a finished run is not held up) and raises the flag when it says so.
/// `cancel` may do more on that thread each time (show progress).
/// A panic in `work` resumes here.
pub fn run_with_stop_flag<T: Send>(
    work: impl FnOnce(&StopFlag) -> T + Send,
    cancel: Option<&dyn Fn() -> bool>,
) -> T {
    let stop = StopFlag::default();
    let Some(cancelled) = cancel else {
        return work(&stop);
    };
    let caller = std::thread::current();
    std::thread::scope(|s| {
        let stop = &stop;
        let running = s.spawn(move || {
            let out = work(stop);
            caller.unpark();
            out
        });
        while !running.is_finished() {
            std::thread::park_timeout(POLL_PERIOD);
            if !stop.raised() && cancelled() {
                stop.raise();
            }
        }
        running
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn never() -> bool {
        false
    }

    fn now() -> bool {
        true
    }

    #[test]
    fn the_flag_is_raised_only_when_cancel_says_so() {
        // (work that waits for the flag, bounded: 5 s)
        let wait = |stop: &StopFlag| {
            for _ in 0..500 {
                if stop.raised() {
                    return true;
                }
                std::thread::sleep(Duration::from_millis(10));
            }
            false
        };
        assert!(run_with_stop_flag(wait, Some(&now)));
        assert!(!run_with_stop_flag(
            |stop: &StopFlag| stop.raised(),
            Some(&never)
        ));
        assert!(!run_with_stop_flag(|stop: &StopFlag| stop.raised(), None));
        assert_eq!(run_with_stop_flag(|_: &StopFlag| 7, Some(&never)), 7);
    }
}
