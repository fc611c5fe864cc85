//! Issue 18 item 2: an IMU vector with a missing cell keeps its other axes
//! through the trial reader (`acc_partial`/`gyr_partial` beside the
//! complete-vector fields), and the writers (CSV and Arrow) write them back.

use std::path::Path;

use limbfuse_core::{Record, Segment};
use limbfuse_io::{TrialLayout, TrialMeta, TrialReader, TrialWriter};
use nalgebra::Vector3;

fn read_all(bytes: Vec<u8>, name: &str) -> Vec<Record> {
    let reader =
        TrialReader::from_reader(Path::new(name), Box::new(std::io::Cursor::new(bytes))).unwrap();
    reader.map(|r| r.unwrap()).collect()
}

#[test]
fn issue_18_a_dropped_cell_keeps_the_other_axes_of_its_vector() {
    let header = "# format: limbfuse-trial/1\n# sample_rate_hz: 100\n\
                  t,thigh_acc_x,thigh_acc_y,thigh_acc_z,thigh_gyr_x,thigh_gyr_y,thigh_gyr_z\n";
    let rows = "0,1.5,9.5,0.25,0.1,0.2,3\n\
                0.01,1.5,9.5,,,,3.5\n\
                0.02,,,,,,\n";
    let recs = read_all(format!("{header}{rows}").into_bytes(), "cells.csv");
    let th = |r: &Record| r.sample.imu[Segment::Thigh.index()];
    assert_eq!(th(&recs[0]).acc, Some(Vector3::new(1.5, 9.5, 0.25)));
    assert_eq!(th(&recs[0]).acc_partial, [None; 3]);
    // one dropped accelerometer cell: the vector is incomplete, x and y stay
    assert_eq!(th(&recs[1]).acc, None);
    assert_eq!(th(&recs[1]).acc_partial, [Some(1.5), Some(9.5), None]);
    // two dropped gyro cells: z stays
    assert_eq!(th(&recs[1]).gyr, None);
    assert_eq!(th(&recs[1]).gyr_axes(), [None, None, Some(3.5)]);
    // every cell missing: nothing at all
    assert!(th(&recs[2]).is_empty());
}

/// Records with complete, partial and missing vectors.
fn records() -> Vec<Record> {
    (0..40)
        .map(|k| {
            let t = k as f64 * 0.01;
            let mut r = Record::default();
            r.sample.t = t;
            for (i, imu) in r.sample.imu.iter_mut().enumerate() {
                let x = (t * (1.0 + i as f64)).sin();
                let cell = |axis: usize, v: f64| (!(k + axis + i).is_multiple_of(5)).then_some(v);
                imu.set_acc_axes([cell(0, x), cell(1, 9.81 + x), cell(2, -x / 3.0)]);
                imu.set_gyr_axes([cell(2, 0.1 * x), cell(3, x * x), cell(4, 2.0 * x)]);
            }
            r
        })
        .collect()
}

#[test]
fn issue_18_partial_vectors_round_trip_through_csv_and_arrow() {
    let mut meta = TrialMeta::trial_v1();
    meta.set("source", "test");
    let mut layout = TrialLayout::walking();
    layout.encoder = [false; 3];
    layout.segment_ref = [false; 4];
    layout.joint_ref = [false; 3];
    let recs = records();
    assert!(recs
        .iter()
        .any(|r| r.sample.imu[1].acc_partial[1].is_some()));
    let mut w = TrialWriter::new(Vec::new(), &meta, layout).unwrap();
    for r in &recs {
        w.write(r).unwrap();
    }
    assert_eq!(read_all(w.finish().unwrap(), "partial.csv"), recs);
    let mut w = TrialWriter::arrow(Vec::new(), &meta, layout).unwrap();
    for r in &recs {
        w.write(r).unwrap();
    }
    // the Arrow reader reads files (it seeks to the footer)
    let path = std::env::temp_dir().join(format!("limbfuse-partial-{}.arrow", std::process::id()));
    std::fs::write(&path, w.finish().unwrap()).unwrap();
    let back: Vec<Record> = TrialReader::open(&path)
        .unwrap()
        .map(|r| r.unwrap())
        .collect();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(back, recs);
}
