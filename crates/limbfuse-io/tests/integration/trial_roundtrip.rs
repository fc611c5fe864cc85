//! Trial and estimate files round-trip bit for bit; missing cells stay missing.

use std::path::Path;

use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Record, Segment};
use limbfuse_io::{EstimateReader, TrialLayout, TrialMeta, TrialReader, TrialWriter};
use nalgebra::Vector3;

fn records() -> Vec<Record> {
    (0..50)
        .map(|k| {
            let t = k as f64 * 0.01 + 1.0 / 3.0;
            let mut r = Record::default();
            r.sample.t = t;
            for (i, imu) in r.sample.imu.iter_mut().enumerate() {
                let x = (t * (i + 1) as f64).sin();
                // A dropout on the shank every 7th sample.
                if !(i == Segment::Shank.index() && k % 7 == 3) {
                    imu.acc = Some(Vector3::new(x, 9.81 + x * 1e-7, -x / 7.0));
                    imu.gyr = Some(Vector3::new(1e-300, x * x, std::f64::consts::PI * x));
                }
            }
            r.sample.encoder = [
                Some(0.1 * t),
                if k % 5 == 0 { None } else { Some(-t) },
                Some(t.cos()),
            ];
            r.reference.segment = [Some(0.0), Some(t), Some(-t), Some(0.5 * t)];
            r.reference.joint = [Some(-t), Some(2.0 * t), Some(-1.5 * t)];
            r
        })
        .collect()
}

#[test]
fn trial_round_trip_is_bit_exact() {
    let mut meta = TrialMeta::trial_v1();
    meta.set("source", "unit test");
    meta.set("g", "9.80665");
    let mut w = TrialWriter::new(Vec::new(), &meta, TrialLayout::walking()).unwrap();
    let recs = records();
    for r in &recs {
        w.write(r).unwrap();
    }
    let bytes = w.finish().unwrap();
    let mut reader =
        TrialReader::from_reader(Path::new("mem.csv"), Box::new(std::io::Cursor::new(bytes)))
            .unwrap();
    assert_eq!(reader.meta().get("source"), Some("unit test"));
    assert_eq!(reader.meta().gravity(), Ok(9.80665));
    assert_eq!(*reader.layout(), TrialLayout::walking());
    let mut back = Vec::new();
    while let Some(r) = reader.next_record().unwrap() {
        back.push(r);
    }
    assert_eq!(back, recs);
    assert!(back[3].sample.imu[Segment::Shank.index()].acc.is_none());
}

#[test]
fn columns_are_found_by_name_in_any_order_and_unknown_ones_ignored() {
    let text = "# note: x\nknee_ref,extra,t,thigh_ref\n0.5,hello,0,0.1\n,world,0.02,0.2\n";
    let mut r =
        TrialReader::from_reader(Path::new("m.csv"), Box::new(std::io::Cursor::new(text))).unwrap();
    let a = r.next_record().unwrap().unwrap();
    let b = r.next_record().unwrap().unwrap();
    assert!(r.next_record().unwrap().is_none());
    assert_eq!(a.reference.joint[1], Some(0.5));
    assert_eq!(a.reference.segment[1], Some(0.1));
    assert_eq!(b.sample.t, 0.02);
    assert_eq!(b.reference.joint[1], None);
}

#[test]
fn estimate_file_reads_angles_and_diagnostics() {
    let text = "# method: test\n# zeta: 0.2\nt,thigh,knee,diag_mode\n0,0.1,0.2,1\n0.01,,0.3,\n";
    let mut r =
        EstimateReader::from_reader(Path::new("e.csv"), Box::new(std::io::Cursor::new(text)))
            .unwrap();
    assert_eq!(r.method(), "test");
    assert_eq!(r.meta().get("zeta"), Some("0.2"));
    assert!(r.has_angle(AngleChannel::Segment(Segment::Thigh)));
    assert!(!r.has_angle(AngleChannel::Segment(Segment::Foot)));
    assert_eq!(r.diagnostic_names().collect::<Vec<_>>(), vec!["mode"]);
    let (line, e) = r.next_estimate().unwrap().unwrap();
    assert_eq!(line, 4);
    assert_eq!(e.segment[1], Some(0.1));
    assert_eq!(e.diag[0], Some(1.0));
    let (_, e) = r.next_estimate().unwrap().unwrap();
    assert_eq!(e.segment[1], None);
    assert_eq!(e.diag[0], None);
}
