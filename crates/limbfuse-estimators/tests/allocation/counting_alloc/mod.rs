//! A global allocator that counts allocations, for the tests that check
//! that per-sample `step` calls allocate nothing (the `allocation` test
//! binary, apart from the other integration tests so that no other test
//! runs under this allocator).
//!
//! Each thread has its own count, and only threads that asked for it count:
//! the first call of [`allocations`] on a thread starts counting there. The
//! test harness's own threads (its output capture, its "running for over 60
//! seconds" notice) allocate too and would otherwise make the count depend
//! on timing (seen once: "sdre allocated 4 times" under load, then clean),
//! and so would the other tests of this binary, which the harness runs in
//! parallel threads.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    /// This thread's allocations since it first asked; `None` before.
    static ALLOCATIONS: Cell<Option<usize>> = const { Cell::new(None) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get().map(|k| k + 1)));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations so far by the calling thread; counting starts on it from its
/// first call on.
pub fn allocations() -> usize {
    ALLOCATIONS.with(|n| {
        let k = n.get().unwrap_or(0);
        n.set(Some(k));
        k
    })
}

/// The count sees this thread's allocations and not another thread's (the
/// tests of this binary run in parallel threads; a count shared by all
/// threads failed this).
#[test]
fn counts_the_calling_threads_allocations_only() {
    let before = allocations();
    let theirs = std::thread::spawn(|| {
        allocations();
        for _ in 0..1000 {
            std::hint::black_box(vec![0u8; 64]);
        }
        allocations()
    })
    .join()
    .unwrap();
    let ours = allocations() - before;
    assert!(theirs >= 1000, "{theirs}");
    assert!(ours < 1000, "{ours}");
    let k = allocations();
    std::hint::black_box(vec![0u8; 64]);
    assert_eq!(allocations() - k, 1);
}
