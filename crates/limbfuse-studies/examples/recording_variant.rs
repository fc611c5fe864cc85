//! Variants of a shared recording that a kept-back recording of the same
//! kind could be (docs/RESULTS.md, "Second audit against kept-back
//! recordings"): rows removed (a time gap), IMU cells emptied over a time
//! window or on every N-th row (dropped packets), the model inputs
//! (stimulation, motor torques) emptied over a time window, the other leg's IMU
//! columns removed, one of this leg's IMUs removed, or the two legs' IMU columns and contact references
//! exchanged without mirroring the readings, the time stamps jittered, or
//! an encoder stuck or re-zeroed, single-sample gyroscope spikes added, or
//! time-stamp glitches (a duplicate row, a swapped pair, a late stamp).
//! Other rates and the mirror
//! image are `limbfuse resample` and `limbfuse mirror`.
//! `cargo run --release -p limbfuse-studies --example recording_variant --
//! TRIAL -o OUT [--drop-rows A:B ...] [--blank A:B ...] [--blank-inputs A:B ...]
//! [--blank-every N [--blank-first K]] [--drop-other-leg] [--drop-imu SEGMENT ...] [--swap-legs] [--jitter-ms MS
//! [--jitter-seed S]] [--stick-encoder JOINT:START:END ...]
//! [--offset-encoder JOINT:START:RAD ...] [--gyro-spikes N [--spike-rad-s A]
//! [--spike-from T] [--spike-seed S]] [--time-glitches N [--glitch-seed S]]`

use std::io::BufWriter;
use std::path::Path;

use clap::Parser;
use limbfuse_core::sample::ModelInputs;
use limbfuse_core::ImuSample;
use limbfuse_io::TrialWriter;
use limbfuse_signal::recording_variants::{add_gyro_spikes, add_time_glitches, jitter_times};
use limbfuse_studies::example_args::RecordingVariantArgs;
use limbfuse_studies::recorded_trial::RecordedTrial;

fn inside(windows: &[(f64, f64)], t: f64) -> bool {
    windows.iter().any(|&(a, b)| (a..b).contains(&t))
}

fn main() {
    let args = RecordingVariantArgs::parse();
    let RecordedTrial {
        meta,
        mut layout,
        records,
    } = RecordedTrial::read(Path::new(&args.trial))
        .unwrap_or_else(|e| panic!("{e} (run from the repository root)"));
    let n_in = records.len();
    let mut out = Vec::with_capacity(n_in);
    // the reading each --stick-encoder window holds, from its first row
    let mut stuck: Vec<Option<Option<f64>>> = vec![None; args.stick_encoder.len()];
    for (row, mut r) in records.into_iter().enumerate() {
        let t = r.sample.t;
        if inside(&args.drop_rows, t) {
            continue;
        }
        let every = args
            .blank_every
            .is_some_and(|n| row >= args.blank_first && (row - args.blank_first) % n.get() == 0);
        if every || inside(&args.blank, t) {
            r.sample.imu = [ImuSample::default(); 4];
            r.sample.other_leg_imu = [ImuSample::default(); 4];
        }
        if inside(&args.blank_inputs, t) {
            r.sample.inputs = ModelInputs::default();
        }
        if args.drop_other_leg {
            r.sample.other_leg_imu = [ImuSample::default(); 4];
        }
        for &i in &args.drop_imu {
            r.sample.imu[i] = ImuSample::default();
        }
        for &(j, (start, rad)) in &args.offset_encoder {
            if t >= start {
                r.sample.encoder[j] = r.sample.encoder[j].map(|e| e + rad);
            }
        }
        for (&(j, window), held) in args.stick_encoder.iter().zip(stuck.iter_mut()) {
            if inside(&[window], t) {
                r.sample.encoder[j] = *held.get_or_insert(r.sample.encoder[j]);
            }
        }
        if args.swap_legs {
            core::mem::swap(&mut r.sample.imu, &mut r.sample.other_leg_imu);
            r.reference.contact.swap(0, 1);
        }
        out.push(r);
    }
    if let Some(ms) = args.jitter_ms {
        jitter_times(&mut out, ms / 1000.0, args.jitter_seed);
    }
    if let Some(n) = args.gyro_spikes {
        let rows = add_gyro_spikes(
            &mut out,
            n,
            args.spike_rad_s,
            args.spike_from,
            args.spike_seed,
        );
        eprintln!(
            "{}: {} gyroscope spikes of {} rad/s",
            args.trial,
            rows.len(),
            args.spike_rad_s
        );
    }
    if let Some(n) = args.time_glitches {
        let g = add_time_glitches(&mut out, n, args.glitch_seed);
        eprintln!(
            "{}: {} time-stamp glitches at rows {:?}",
            args.trial,
            g.len(),
            g
        );
    }
    if args.drop_other_leg {
        layout.other_acc = [false; 4];
        layout.other_gyr = [false; 4];
    }
    for &i in &args.drop_imu {
        layout.acc[i] = false;
        layout.gyr[i] = false;
    }
    if args.swap_legs {
        core::mem::swap(&mut layout.acc, &mut layout.other_acc);
        core::mem::swap(&mut layout.gyr, &mut layout.other_gyr);
    }
    let path = Path::new(&args.output);
    let file = std::fs::File::create(path).unwrap_or_else(|e| panic!("{}: {e}", args.output));
    let mut w = TrialWriter::for_path(path, BufWriter::new(file), &meta, layout)
        .unwrap_or_else(|e| panic!("{}: {e}", args.output));
    for r in &out {
        w.write(r)
            .unwrap_or_else(|e| panic!("{}: {e}", args.output));
    }
    w.finish()
        .unwrap_or_else(|e| panic!("{}: {e}", args.output));
    eprintln!(
        "{}: {n_in} rows -> {} rows in {}",
        args.trial,
        out.len(),
        args.output
    );
}
