//! Two-leg recordings and gait references (SPEC section 2, docs/GAIT_EVENTS.md):
//! the other leg's IMU columns, `contact_left_ref` / `contact_right_ref`,
//! `speed_ref`, written and read back; bad cells and a bad `# leg:` refused.

use std::path::Path;

use limbfuse_core::{Record, Segment, Side};
use limbfuse_io::{TrialLayout, TrialMeta, TrialReader, TrialWriter};
use nalgebra::Vector3;

fn read(text: &str) -> Result<(TrialLayout, Vec<Record>), limbfuse_io::FileError> {
    let mut r = TrialReader::from_reader(
        Path::new("two.csv"),
        Box::new(std::io::Cursor::new(text.as_bytes().to_vec())),
    )?;
    let layout = *r.layout();
    let mut out = vec![];
    while let Some(rec) = r.next_record()? {
        out.push(rec);
    }
    Ok((layout, out))
}

#[test]
fn other_leg_and_gait_references_round_trip() {
    let foot = Segment::Foot.index();
    let mut layout = TrialLayout {
        leg: Side::Left,
        ..TrialLayout::default()
    };
    layout.acc[foot] = true;
    layout.other_acc[foot] = true;
    layout.other_gyr[foot] = true;
    layout.contact_ref = [true, true];
    layout.speed_ref = true;
    let mut meta = TrialMeta::trial_v1();
    meta.set("leg", "left");
    let mut w = TrialWriter::new(Vec::new(), &meta, layout).unwrap();
    let mut records = vec![];
    for k in 0..3 {
        let mut r = Record::default();
        r.sample.t = k as f64 * 0.01;
        r.sample.imu[foot].acc = Some(Vector3::new(1.0, 2.0, k as f64));
        r.sample.other_leg_imu[foot].acc = Some(Vector3::new(3.0, 4.0, 5.0));
        r.sample.other_leg_imu[foot].gyr = Some(Vector3::new(0.5, -0.5, k as f64));
        r.reference.contact = [Some(k != 1), if k == 2 { None } else { Some(false) }];
        r.reference.speed = (k > 0).then_some(1.25);
        w.write(&r).unwrap();
        records.push(r);
    }
    let text = String::from_utf8(w.finish().unwrap()).unwrap();
    assert!(
        text.contains("foot_right_gyr_z") && text.contains("contact_left_ref"),
        "{text}"
    );
    let (l, back) = read(&text).unwrap();
    assert_eq!(l, layout);
    assert_eq!(back, records);
}

#[test]
fn a_contact_cell_must_be_0_or_1_and_leg_must_be_a_side() {
    let e = read("t,contact_left_ref\n0,1\n0.01,0.5\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("two.csv:3") && e.contains("contact_left_ref") && e.contains("0.5"),
        "{e}"
    );
    let e = read("# leg: middle\nt,foot_acc_x,foot_acc_y,foot_acc_z\n0,1,2,3\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("leg: middle") && e.contains("`left` or `right`"),
        "{e}"
    );
}
