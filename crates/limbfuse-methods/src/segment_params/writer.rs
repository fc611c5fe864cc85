//! Writing segment-filter parameters as a TOML parameter file that reads
//! back to the same parameters bit for bit (what `limbfuse tune` and
//! `limbfuse params` write).

use std::fmt::Write as _;
use std::path::Path;

use limbfuse_core::discretize::Discretization;
use limbfuse_core::kalman::CovarianceUpdate;
use limbfuse_core::Segment;

use super::{FilterParams, ParamsFileError};

/// A float as a TOML literal that reads back to the same bits.
fn lit(v: f64) -> String {
    if v.is_infinite() {
        if v > 0.0 { "inf" } else { "-inf" }.to_string()
    } else if v.is_nan() {
        "nan".to_string()
    } else {
        // Debug prints the shortest representation that round-trips, with a
        // decimal point or an exponent, both valid TOML floats.
        format!("{v:?}")
    }
}

/// The parameters as a TOML parameter file, every value explicit. `header`
/// lines are written first as `#` comments (provenance).
pub fn to_toml(params: &FilterParams, header: &[String]) -> String {
    let c = params.common();
    let mut s = String::new();
    for h in header {
        for line in h.lines() {
            let _ = writeln!(s, "# {line}");
        }
    }
    let _ = writeln!(
        s,
        "# limbfuse segment-filter parameters (docs/TUNING.md lists every key)."
    );
    let _ = writeln!(
        s,
        "# Every value is explicit; the preset only fills keys left out."
    );
    let _ = writeln!(s, "method = \"{}\"", params.method().name());
    let _ = writeln!(s, "preset = \"default\"");
    let _ = writeln!(s, "gravity = {}  # m/s^2", lit(c.gravity));
    let _ = writeln!(s, "p0_angle_sigma = {}  # rad", lit(c.p0_angle_sigma));
    let _ = writeln!(s, "p0_bias_sigma = {}  # rad/s", lit(c.p0_bias_sigma));
    let _ = writeln!(s, "loop_mode = \"{}\"", c.loop_mode.label());
    let _ = writeln!(
        s,
        "discretization = \"{}\"",
        match c.discretization {
            Discretization::Exact => "exact",
            Discretization::Euler => "euler",
        }
    );
    let _ = writeln!(
        s,
        "covariance_update = \"{}\"",
        match c.covariance_update {
            CovarianceUpdate::Joseph => "joseph",
            CovarianceUpdate::Standard => "standard",
        }
    );
    let _ = writeln!(
        s,
        "accel_hold_s = {}  # s, 0 = off",
        lit(c.accel_gate.hold_s)
    );
    let _ = writeln!(
        s,
        "accel_max_rate = {}  # rad/s, inf = off",
        lit(c.accel_gate.max_rate)
    );
    if c.startup_s > 0.0 {
        // (written only when on: files of the papers' start stay as they were)
        let _ = writeln!(s, "startup_s = {}  # s, 0 = off", lit(c.startup_s));
    }
    if c.first_sample_start {
        // (written only when on, as `startup_s`)
        let _ = writeln!(
            s,
            "first_sample_start = true  # the start before 2026-12-06"
        );
    }
    if !c.rate_spike_test && !matches!(params, FilterParams::Local(_)) {
        // (written only when off: the default files stay as they were)
        let _ = writeln!(
            s,
            "rate_spike_test = false  # apply every gyroscope reading the sample gate passes (the papers')"
        );
    }
    let arr = |v: [f64; 3]| format!("[{}, {}, {}]", lit(v[0]), lit(v[1]), lit(v[2]));
    match params {
        FilterParams::Local(p) => {
            let _ = writeln!(s, "min_reliable = {}", p.min_reliable);
        }
        FilterParams::Mjls(p) => {
            let _ = writeln!(
                s,
                "encoder_sigma = {}  # rad, hip, knee, ankle",
                arr(p.encoder_sigma)
            );
            let _ = writeln!(s, "when_unreliable = \"{}\"", p.when_unreliable.label());
        }
        FilterParams::Global(p) => {
            let _ = writeln!(s, "min_reliable = {}", p.min_reliable);
            if p.relative_sigma.iter().all(Option::is_some) {
                let _ = writeln!(
                    s,
                    "relative_sigma = {}  # rad, hip, knee, ankle rows",
                    arr(p.resolved_relative_sigma())
                );
            } else {
                let _ = writeln!(
                    s,
                    "# relative_sigma left out: derived as sqrt(sigma_a,i^2 + sigma_a,i+1^2)"
                );
            }
        }
    }
    for seg in Segment::ALL {
        let n = &c.segments[seg.index()];
        let _ = writeln!(s, "\n[segments.{}]", seg.name());
        let _ = writeln!(s, "gyro_noise = {}  # rad/s/sqrt(Hz)", lit(n.gyro_noise));
        let _ = writeln!(s, "bias_drive = {}  # rad/s/sqrt(s)", lit(n.bias_drive));
        let _ = writeln!(s, "bias_tau = {}  # s", lit(n.bias_tau));
        let _ = writeln!(s, "accel_angle_sigma = {}  # rad", lit(n.accel_angle_sigma));
        let _ = writeln!(s, "zeta = {}  # m/s^2", lit(n.zeta));
        let _ = writeln!(
            s,
            "initial_gyro_bias = {}  # rad/s",
            lit(c.initial_gyro_bias[seg.index()])
        );
    }
    s
}

/// Writes [`to_toml`] to `path` (whole or not at all, [`limbfuse_io::AtomicFile`]).
pub fn save_params(
    path: &Path,
    params: &FilterParams,
    header: &[String],
) -> Result<(), ParamsFileError> {
    limbfuse_io::AtomicFile::write(path, to_toml(params, header)).map_err(|source| {
        ParamsFileError::Io {
            path: path.to_path_buf(),
            source,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn float_literals_round_trip() {
        for v in [
            1e-5,
            0.1 + 0.2,
            9.81,
            1e300,
            f64::INFINITY,
            -0.0,
            2.0,
            123456789.0,
        ] {
            let t = format!("x = {}", lit(v));
            let back: toml::Table = toml::from_str(&t).unwrap();
            assert_eq!(back["x"].as_float().unwrap().to_bits(), v.to_bits(), "{t}");
        }
    }
}
