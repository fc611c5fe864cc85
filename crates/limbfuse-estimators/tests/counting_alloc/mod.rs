//! A global allocator that counts allocations, for the tests that check
//! that per-sample `step` calls allocate nothing. Each test binary that
//! declares `mod counting_alloc;` gets its own counter.
//!
//! Only allocations of threads that asked for the count are counted: the
//! first call of [`allocations`] on a thread starts counting there. The test
//! harness's own threads (its output capture, its "running for over 60
//! seconds" notice) allocate too and would otherwise make the count depend
//! on timing (seen once: "sdre allocated 4 times" under load, then clean).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    static COUNTED: Cell<bool> = const { Cell::new(false) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTED.try_with(Cell::get).unwrap_or(false) {
            ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations so far by the threads that asked; counting starts on the
/// calling thread from this call on.
pub fn allocations() -> usize {
    COUNTED.with(|c| c.set(true));
    ALLOCATIONS.load(Ordering::SeqCst)
}
