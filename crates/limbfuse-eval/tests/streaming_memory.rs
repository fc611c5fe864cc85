//! Issue 2: estimating a long trial must not hold the trial in memory. A
//! trial file is generated on the fly (never stored), read by `TrialReader`,
//! estimated and written by `EstimateWriter` to a sink; the peak heap use
//! must not grow with the number of rows.

use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Read;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use limbfuse_core::runner::{run, Observer};
use limbfuse_estimators::segment_kf::MarkovJumpKf;
use limbfuse_eval::{AngleMetrics, EvalOptions};
use limbfuse_io::{EstimateWriter, TrialReader};

struct Peak;
static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Peak {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let now = CURRENT.fetch_add(l.size(), Ordering::SeqCst) + l.size();
        PEAK.fetch_max(now, Ordering::SeqCst);
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        CURRENT.fetch_sub(l.size(), Ordering::SeqCst);
        unsafe { System.dealloc(p, l) }
    }
}

#[global_allocator]
static GLOBAL: Peak = Peak;

/// A trial file of `rows` rows produced as it is read.
struct GeneratedTrial {
    rows: usize,
    next: usize,
    pending: Vec<u8>,
    pos: usize,
}

impl GeneratedTrial {
    fn new(rows: usize) -> Self {
        let mut header = String::from("# format: limbfuse-trial/1\nt");
        for s in ["trunk", "thigh", "shank", "foot"] {
            for q in ["acc", "gyr"] {
                for a in ["x", "y", "z"] {
                    header += &format!(",{s}_{q}_{a}");
                }
            }
        }
        header += ",hip_enc,knee_enc,ankle_enc,thigh_ref,knee_ref\n";
        GeneratedTrial {
            rows,
            next: 0,
            pending: header.into_bytes(),
            pos: 0,
        }
    }
}

impl Read for GeneratedTrial {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.pos == self.pending.len() {
            if self.next == self.rows {
                return Ok(0);
            }
            let t = self.next as f64 * 0.001;
            let th = 0.3 * (t * 6.0).sin();
            let mut line = format!("{t}");
            for _ in 0..4 {
                line += &format!(
                    ",{},{},0,0,0,{}",
                    9.81 * th.sin(),
                    9.81 * th.cos(),
                    1.8 * (t * 6.0).cos()
                );
            }
            line += &format!(",0,0,0,{th},0\n");
            self.pending = line.into_bytes();
            self.pos = 0;
            self.next += 1;
        }
        let n = buf.len().min(self.pending.len() - self.pos);
        buf[..n].copy_from_slice(&self.pending[self.pos..self.pos + n]);
        self.pos += n;
        Ok(n)
    }
}

fn peak_bytes_for(rows: usize) -> usize {
    let reader = TrialReader::from_reader(
        Path::new("generated.csv"),
        Box::new(GeneratedTrial::new(rows)),
    )
    .unwrap();
    let mut est = MarkovJumpKf::default();
    let mut writer = EstimateWriter::new(std::io::sink());
    let mut metrics = AngleMetrics::new("mjls", EvalOptions::default());
    let base = CURRENT.load(Ordering::SeqCst);
    PEAK.store(base, Ordering::SeqCst);
    let observers: &mut [&mut dyn Observer] = &mut [&mut writer, &mut metrics];
    let summary = run(&mut est, reader, observers).unwrap();
    assert_eq!(summary.n_samples, rows as u64);
    assert!(metrics.evaluation().n_samples == rows as u64);
    PEAK.load(Ordering::SeqCst) - base
}

#[test]
fn peak_memory_does_not_grow_with_trial_length() {
    let small = peak_bytes_for(2_000);
    let large = peak_bytes_for(200_000);
    println!("peak heap: {small} B for 2k rows, {large} B for 200k rows");
    // 200k rows of ~300 bytes are 60 MB of text; a streaming run stays at the
    // reader's buffers (tens of kB) whatever the length.
    assert!(large < 1 << 20, "peak {large} B");
    assert!(
        large <= small + 4096,
        "peak grew from {small} B to {large} B"
    );
}
