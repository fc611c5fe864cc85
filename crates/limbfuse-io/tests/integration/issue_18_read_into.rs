//! Issue 18 item 6 (copies cut): `TrialReader::read_into` parses each row
//! into one reused record and must overwrite every field, so that a cell
//! present in one row never survives into the next row where it is empty;
//! `skip_references` leaves the references empty and does not parse them.

use std::path::Path;

use limbfuse_core::runner::{run_from, Observer, RecordSource};
use limbfuse_core::{Estimate, Estimator, EstimatorError, Outputs, Record, Sample};
use limbfuse_io::TrialReader;

/// Every kind of column the reader knows, one row full and one row empty.
const TRIAL: &str = "# leg: right\n\
t,trunk_acc_x,trunk_acc_y,trunk_acc_z,trunk_gyr_x,trunk_gyr_y,trunk_gyr_z,\
thigh_quat_w,thigh_quat_x,thigh_quat_y,thigh_quat_z,foot_left_acc_x,foot_left_acc_y,foot_left_acc_z,\
knee_enc,u_ke,tau_knee_motor,com_meas_x,thigh_ref,knee_ref,com_x,com_y,com_z,com_vx,com_vy,com_vz,\
phase_ref,contact_left_ref,contact_right_ref,speed_ref\n\
0.00,1,2,3,4,5,6,1,0,0,0,7,8,9,0.1,0.2,0.3,0.4,0.5,0.6,1,2,3,4,5,6,DS,1,0,1.2\n\
0.01,,,,,,,,,,,,,,,,,,,,,,,,,,,,,\n\
0.02,1,,3,,5,,1,0,0,0,7,8,,0.1,,,,0.5,,,,,,,,SS1,,1,\n";

fn reader() -> TrialReader {
    TrialReader::from_reader(
        Path::new("all.csv"),
        Box::new(std::io::Cursor::new(TRIAL.as_bytes().to_vec())),
    )
    .unwrap()
}

#[test]
fn issue_18_read_into_overwrites_every_field_of_a_reused_record() {
    let mut fresh = reader();
    let mut reused = reader();
    let mut rec = Record::default();
    let mut n = 0;
    while let Some(expected) = fresh.next_record().unwrap() {
        assert!(reused.read_into(&mut rec).unwrap());
        assert_eq!(rec, expected, "row {n}");
        n += 1;
    }
    assert_eq!(n, 3);
    assert!(!reused.read_into(&mut rec).unwrap());
    assert_eq!(fresh.content_hash(), reused.content_hash());
}

#[test]
fn issue_18_skipped_references_stay_empty_and_unparsed() {
    let mut full = reader();
    // A reference cell that is not a number: refused when read, ignored when skipped.
    let bad = TRIAL.replace("0.5,0.6,1,2,3", "0.5,oops,1,2,3");
    let mut skipping = TrialReader::from_reader(
        Path::new("bad.csv"),
        Box::new(std::io::Cursor::new(bad.as_bytes().to_vec())),
    )
    .unwrap();
    skipping.skip_references();
    assert!(skipping.layout().joint_ref[1], "the layout still lists it");
    while let Some(expected) = full.next_record().unwrap() {
        let got = skipping.next_record().unwrap().unwrap();
        assert_eq!(got.sample, expected.sample);
        assert_eq!(got.reference, Default::default());
    }
    assert!(skipping.next_record().unwrap().is_none());
    let mut strict = TrialReader::from_reader(
        Path::new("bad.csv"),
        Box::new(std::io::Cursor::new(bad.into_bytes())),
    )
    .unwrap();
    let e = strict.next_record().unwrap_err().to_string();
    assert!(e.contains("knee_ref"), "{e}");
}

/// An estimator that echoes the time and knee encoder (an estimate built by
/// the default `step_into`).
struct Echo;

impl Estimator for Echo {
    fn name(&self) -> &'static str {
        "echo"
    }
    fn outputs(&self) -> Outputs {
        Outputs::default()
    }
    fn describe_parameters(&self, _out: &mut dyn std::fmt::Write) -> std::fmt::Result {
        Ok(())
    }
    fn reset(&mut self) {}
    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let mut e = Estimate::empty(sample.t);
        e.joint[1] = sample.encoder[1];
        Ok(e)
    }
}

#[derive(Default)]
struct Seen(Vec<(f64, Option<f64>)>);

impl Observer for Seen {
    fn observe(
        &mut self,
        record: &Record,
        e: &Estimate,
    ) -> Result<(), limbfuse_core::runner::BoxError> {
        assert_eq!(record.sample.t, e.t);
        self.0.push((e.t, e.joint[1]));
        Ok(())
    }
}

#[test]
fn issue_18_the_runner_reads_a_trial_into_one_record() {
    let mut seen = Seen::default();
    let mut r = reader();
    let source: &mut dyn RecordSource<Error = limbfuse_io::FileError> = &mut r;
    let s = run_from(&mut Echo, source, &mut [&mut seen]).unwrap();
    assert_eq!(s.n_samples, 3);
    assert_eq!(
        seen.0,
        vec![(0.0, Some(0.1)), (0.01, None), (0.02, Some(0.1))]
    );
}
