//! Issue 13: adding a method means writing its estimator and its
//! `MethodDef`. This test adds a trivial method (`constant-angle`: every
//! segment at a fixed angle) outside the crate and takes it through the same
//! generic path the registry uses for every method: a typed parameter file
//! with unknown keys rejected, the `method` line checked, flags ignored,
//! the columns it needs checked, the estimator built and stepped.
//! Registering it for `--method` is then one line in `registry.rs`.

use std::path::Path;

use limbfuse_core::estimator::{EstimatorError, Outputs};
use limbfuse_core::{Estimate, Estimator, Sample};
use limbfuse_io::{TrialLayout, TrialMeta};
use limbfuse_methods::{
    build_with, read_file, resolve_with, ChannelNeeds, MethodDef, MethodError, MethodFile,
    MethodFlags, MethodInfo,
};
use serde::Deserialize;

/// The estimator: every segment at `angle`.
struct ConstantAngle {
    angle: f64,
}

impl Estimator for ConstantAngle {
    fn name(&self) -> &'static str {
        "constant-angle"
    }
    fn outputs(&self) -> Outputs {
        Outputs {
            segment: [true; 4],
            ..Outputs::default()
        }
    }
    fn describe_parameters(&self, out: &mut dyn core::fmt::Write) -> core::fmt::Result {
        writeln!(out, "angle = {}", self.angle)
    }
    fn reset(&mut self) {}
    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let mut e = Estimate::empty(sample.t);
        e.segment = [Some(self.angle); 4];
        Ok(e)
    }
}

/// Its parameter file.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct ConstantAngleFile {
    method: Option<String>,
    angle: Option<f64>,
}

impl MethodFile for ConstantAngleFile {
    fn method(&self) -> Option<&str> {
        self.method.as_deref()
    }
}

/// The method.
struct ConstantAngleMethod;

impl MethodDef for ConstantAngleMethod {
    const INFO: MethodInfo = MethodInfo::new(
        "constant-angle",
        "test: every segment at a fixed angle",
        "the thigh gyro (to show the column check)",
        "angle (rad)",
    )
    .needing(
        ChannelNeeds {
            gyr: [false, true, false, false],
            ..ChannelNeeds::NONE
        },
        "needs the thigh gyro",
    );
    type Settings = f64;

    fn resolve(file: Option<(&str, &Path)>, _: &MethodFlags) -> Result<f64, MethodError> {
        let f: ConstantAngleFile = read_file::<Self, _>(file)?;
        Ok(f.angle.unwrap_or(0.0))
    }

    fn build(
        angle: &f64,
        _: &TrialMeta,
        _: &TrialLayout,
    ) -> Result<Box<dyn Estimator + Send>, MethodError> {
        Ok(Box::new(ConstantAngle { angle: *angle }))
    }

    fn default_file() -> String {
        "method = \"constant-angle\"\nangle = 0.0\n".into()
    }
}

fn layout_with_thigh_gyro() -> TrialLayout {
    let mut l = TrialLayout::default();
    l.gyr[1] = true;
    l
}

#[test]
fn a_new_method_resolves_builds_and_runs_through_the_generic_path() {
    let path = Path::new("c.toml");
    let flags = MethodFlags::default();
    let angle =
        resolve_with::<ConstantAngleMethod>(Some(("angle = 0.25\n", path)), &flags).unwrap();
    assert_eq!(angle, 0.25);
    let defaults = ConstantAngleMethod::default_file();
    assert_eq!(
        resolve_with::<ConstantAngleMethod>(Some((&defaults, path)), &flags).unwrap(),
        0.0
    );
    let mut est = build_with::<ConstantAngleMethod>(
        &angle,
        &TrialMeta::trial_v1(),
        &layout_with_thigh_gyro(),
    )
    .unwrap();
    let e = est.step(&Sample::empty(0.0)).unwrap();
    assert_eq!(e.segment, [Some(0.25); 4]);
}

#[test]
fn the_generic_path_rejects_what_does_not_belong_to_the_new_method() {
    let path = Path::new("c.toml");
    let flags = MethodFlags::default();
    let e = resolve_with::<ConstantAngleMethod>(Some(("angel = 0.25\n", path)), &flags)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("c.toml:1:1:") && e.contains("angel"), "{e}");
    let e = resolve_with::<ConstantAngleMethod>(Some(("method = \"mjls\"\n", path)), &flags)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("\"mjls\"") && e.contains("`constant-angle`"),
        "{e}"
    );
    let e =
        build_with::<ConstantAngleMethod>(&0.0, &TrialMeta::trial_v1(), &TrialLayout::default())
            .err()
            .expect("no thigh gyro")
            .to_string();
    assert!(
        e.contains("constant-angle") && e.contains("thigh_gyr_x/y/z"),
        "{e}"
    );
}
