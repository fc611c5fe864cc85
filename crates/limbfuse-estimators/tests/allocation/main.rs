//! The per-sample `step` calls allocate nothing: one binary with a counting
//! global allocator (`counting_alloc`, counts per thread), apart from the
//! other integration tests.

mod chain_no_allocation;
mod counting_alloc;
mod fes_no_allocation;
mod gait_events_no_allocation;
mod no_allocation;
