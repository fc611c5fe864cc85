//! Parameter files: presets, overrides, round trip, and errors that name the
//! file, the key and the accepted range.

use std::path::Path;

use limbfuse_estimators::segment_kf::{LoopMode, WhenUnreliable};
use limbfuse_methods::segment_params::{
    load_params, parse_params, save_params, to_toml, FilterMethod, FilterParams, Preset,
};

fn parse(text: &str, m: FilterMethod) -> Result<FilterParams, String> {
    parse_params(text, Path::new("p.toml"), m).map_err(|e| e.to_string())
}

#[test]
fn empty_file_is_the_default_preset_and_paper_preset_is_selectable() {
    for m in FilterMethod::ALL {
        assert_eq!(
            parse("", m).unwrap(),
            FilterParams::preset(m, Preset::Default)
        );
        assert_eq!(
            parse("preset = \"paper-2014\"", m).unwrap(),
            FilterParams::preset(m, Preset::Paper2014)
        );
    }
}

#[test]
fn overrides_apply_all_then_per_segment() {
    let text = r#"
        method = "mjls"
        gravity = 9.8
        loop_mode = "open"
        discretization = "euler"
        covariance_update = "standard"
        encoder_sigma = [0.01, 0.02, 0.03]
        when_unreliable = "encoders-only"
        [segments.all]
        zeta = 0.5
        bias_tau = inf
        [segments.foot]
        zeta = 1
        gyro_noise = 2e-4
    "#;
    let p = parse(text, FilterMethod::Mjls).unwrap();
    let FilterParams::Mjls(m) = p else { panic!() };
    assert_eq!(m.common.gravity, 9.8);
    assert_eq!(m.common.loop_mode, LoopMode::Open);
    assert_eq!(m.encoder_sigma, [0.01, 0.02, 0.03]);
    assert_eq!(m.when_unreliable, WhenUnreliable::EncodersOnly);
    assert_eq!(m.common.zetas(), [0.5, 0.5, 0.5, 1.0]);
    assert_eq!(m.common.segments[3].gyro_noise, 2e-4);
    assert!(m.common.segments[0].bias_tau.is_infinite());
    let g = parse(
        "relative_sigma = 0.3\nmin_reliable = 3",
        FilterMethod::Global,
    )
    .unwrap();
    let FilterParams::Global(g) = g else { panic!() };
    assert_eq!(g.relative_sigma, [Some(0.3); 3]);
    assert_eq!(g.min_reliable, 3);
}

#[test]
fn written_file_reads_back_to_the_same_parameters() {
    let d = tempfile::tempdir().unwrap();
    for m in FilterMethod::ALL {
        for preset in [Preset::Default, Preset::Paper2014] {
            let mut p = FilterParams::preset(m, preset);
            p.common_mut().segments[1].gyro_noise = 0.1 + 0.2; // not a short decimal
            p.common_mut().segments[2].zeta = 1.0 / 3.0;
            p.common_mut().initial_gyro_bias[3] = -1e-3;
            p.common_mut().accel_gate.hold_s = 0.01;
            if preset == Preset::Paper2014 {
                p.common_mut().accel_gate.max_rate = 0.7;
                p.common_mut().startup_s = 1.0 / 3.0;
                if m != FilterMethod::Local {
                    p.common_mut().rate_spike_test = false;
                }
            }
            let path = d.path().join(format!("{}.toml", m.name()));
            save_params(&path, &p, &["tuned by a test".into()]).unwrap();
            let back = load_params(&path, m).unwrap();
            assert_eq!(back, p, "{}", to_toml(&p, &[]));
        }
    }
}

#[test]
fn unknown_key_names_the_file_line_and_key() {
    let e = parse("[segments.thigh]\ngyro_nois = 1e-4\n", FilterMethod::Local).unwrap_err();
    assert!(e.starts_with("p.toml:2:"), "{e}");
    assert!(e.contains("gyro_nois"), "{e}");
    let e = parse("sigma = 1", FilterMethod::Local).unwrap_err();
    assert!(e.contains("p.toml:1:") && e.contains("`sigma`"), "{e}");
    let e = parse("[segments.knee]\nzeta = 1", FilterMethod::Local).unwrap_err();
    assert!(e.contains("knee"), "{e}");
    let e = parse("loop_mode = \"half\"", FilterMethod::Local).unwrap_err();
    assert!(e.contains("half") && e.contains("closed"), "{e}");
    let e = parse("gravity = \"high\"", FilterMethod::Local).unwrap_err();
    assert!(e.contains("p.toml:1:"), "{e}");
    let e = parse("x = [", FilterMethod::Local).unwrap_err();
    assert!(e.starts_with("p.toml:1:"), "{e}");
}

#[test]
fn bad_values_name_the_key_and_range() {
    let e = parse("[segments.thigh]\nzeta = -1", FilterMethod::Local).unwrap_err();
    assert!(
        e.contains("p.toml") && e.contains("`segments.thigh.zeta` = -1") && e.contains("> 0"),
        "{e}"
    );
    let e = parse("[segments.all]\nbias_tau = 0", FilterMethod::Global).unwrap_err();
    assert!(
        e.contains("segments.all.bias_tau") && e.contains("infinity allowed"),
        "{e}"
    );
    let e = parse("min_reliable = 7", FilterMethod::Local).unwrap_err();
    assert!(
        e.contains("`min_reliable` = 7") && e.contains("1..=4"),
        "{e}"
    );
    let e = parse("gravity = nan", FilterMethod::Mjls).unwrap_err();
    assert!(e.contains("`gravity`"), "{e}");
    let e = parse("encoder_sigma = [1, 2]", FilterMethod::Mjls).unwrap_err();
    assert!(
        e.contains("encoder_sigma") && e.contains("3 numbers"),
        "{e}"
    );
    let e = parse("encoder_sigma = 0.01", FilterMethod::Local).unwrap_err();
    assert!(
        e.contains("`encoder_sigma` applies to method `mjls` only"),
        "{e}"
    );
    let e = parse("method = \"global\"", FilterMethod::Local).unwrap_err();
    assert!(e.contains("--method global"), "{e}");
    let e = load_params(Path::new("/nonexistent/p.toml"), FilterMethod::Local)
        .unwrap_err()
        .to_string();
    assert!(e.contains("/nonexistent/p.toml"), "{e}");
}

#[test]
fn accelerometer_gate_keys_apply_to_every_method_and_are_checked() {
    for m in FilterMethod::ALL {
        let p = parse("accel_hold_s = 0.01\naccel_max_rate = 1.5", m).unwrap();
        assert_eq!(p.common().accel_gate.hold_s, 0.01);
        assert_eq!(p.common().accel_gate.max_rate, 1.5);
        let p = parse("", m).unwrap();
        assert!(p.common().accel_gate.is_off());
    }
    let e = parse("accel_hold_s = -0.01", FilterMethod::Mjls).unwrap_err();
    assert!(
        e.contains("`accel_hold_s` = -0.01") && e.contains(">= 0"),
        "{e}"
    );
    let e = parse("accel_max_rate = 0", FilterMethod::Global).unwrap_err();
    assert!(
        e.contains("`accel_max_rate` = 0") && e.contains("infinity = off"),
        "{e}"
    );
}

#[test]
fn issue_14_run_in_key_applies_to_every_method_and_is_checked() {
    for m in FilterMethod::ALL {
        assert_eq!(parse("startup_s = 2", m).unwrap().common().startup_s, 2.0);
        assert_eq!(parse("", m).unwrap().common().startup_s, 0.0);
        // written only when on: a file of the papers' filters is unchanged
        assert!(!to_toml(&FilterParams::preset(m, Preset::Default), &[]).contains("startup_s"));
    }
    let e = parse("startup_s = -1", FilterMethod::Local).unwrap_err();
    assert!(
        e.contains("`startup_s` = -1") && e.contains("0 (off) to 30 s"),
        "{e}"
    );
}

#[test]
fn issue_18_rate_spike_test_key_for_the_filters_with_encoder_rows() {
    for m in [FilterMethod::Mjls, FilterMethod::Global] {
        assert!(parse("", m).unwrap().common().rate_spike_test);
        let off = parse("rate_spike_test = false", m).unwrap();
        assert!(!off.common().rate_spike_test);
        // written only when off: a default file is unchanged
        assert!(
            !to_toml(&FilterParams::preset(m, Preset::Default), &[]).contains("rate_spike_test")
        );
        assert!(to_toml(&off, &[]).contains("rate_spike_test = false"));
    }
    // `local` has no encoder rows: the key means nothing there
    let e = parse("rate_spike_test = false", FilterMethod::Local).unwrap_err();
    assert!(e.contains("rate_spike_test"), "{e}");
    let e = parse("rate_spike_test = 0", FilterMethod::Mjls).unwrap_err();
    assert!(
        e.starts_with("p.toml:1:") && e.contains("expected a boolean"),
        "{e}"
    );
}
