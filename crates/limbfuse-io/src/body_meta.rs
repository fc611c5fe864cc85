//! Body geometry in trial metadata (limbfuse extension of SPEC section 2,
//! docs/CHAIN.md "Geometry metadata"):
//!
//! ```text
//! # imu_mounts_m: trunk (-0.100, +0.080, -0.090); thigh (0, -0.214, 0.08); shank (...); foot (...)
//! # segment_lengths_m: thigh 0.429; shank 0.431
//! # height_m: 1.75
//! ```
//!
//! `imu_mounts_m` gives each IMU's position `(x, y[, z])` in metres in its
//! segment's frame (x forward, y up, z right in upright standing; origins:
//! trunk and thigh at the hip joint centre, shank at the knee, foot at the
//! ankle); segments may be left out, `z` defaults to 0, and text after an
//! entry's closing parenthesis is a comment. `segment_lengths_m` gives the
//! hip-knee (`thigh`) and knee-ankle (`shank`) distances. `height_m` is the
//! body height the anthropometric defaults scale with.

use crate::TrialMeta;

/// Metadata key of the IMU positions.
pub const IMU_MOUNTS_KEY: &str = "imu_mounts_m";
/// Metadata key of the segment lengths.
pub const SEGMENT_LENGTHS_KEY: &str = "segment_lengths_m";
/// Metadata key of the body height.
pub const HEIGHT_KEY: &str = "height_m";

/// Metadata key of the free-text description of the subject (SPEC
/// section 2 keeps unknown keys; limbfuse reads lengths from it as a last
/// resort, [`subject_length`]).
pub const SUBJECT_KEY: &str = "subject";

const SEGMENTS: [&str; 4] = ["trunk", "thigh", "shank", "foot"];

/// A geometry entry of the metadata that does not parse.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("metadata `# {key}: {value}`: {problem}")]
pub struct BodyMetaError {
    /// The key.
    pub key: &'static str,
    /// Its value.
    pub value: String,
    /// What is wrong, and what was expected.
    pub problem: String,
}

/// The body geometry a trial's metadata states (each part optional).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyMeta {
    /// IMU position per segment (trunk, thigh, shank, foot), metres.
    pub imu_position: [Option<[f64; 3]>; 4],
    /// Hip-knee distance (m).
    pub thigh_length: Option<f64>,
    /// Knee-ankle distance (m).
    pub shank_length: Option<f64>,
    /// Body height (m).
    pub height: Option<f64>,
}

fn number(key: &'static str, value: &str, text: &str) -> Result<f64, BodyMetaError> {
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| BodyMetaError {
            key,
            value: value.to_string(),
            problem: format!("`{}` is not a finite number", text.trim()),
        })
}

fn segment_index(key: &'static str, value: &str, name: &str) -> Result<usize, BodyMetaError> {
    SEGMENTS
        .iter()
        .position(|s| *s == name)
        .ok_or_else(|| BodyMetaError {
            key,
            value: value.to_string(),
            problem: format!("unknown segment `{name}` (expected trunk, thigh, shank or foot)"),
        })
}

/// Parses an `imu_mounts_m` value.
pub fn parse_imu_mounts(value: &str) -> Result<[Option<[f64; 3]>; 4], BodyMetaError> {
    let key = IMU_MOUNTS_KEY;
    let err = |problem: String| BodyMetaError {
        key,
        value: value.to_string(),
        problem,
    };
    let mut out = [None; 4];
    for entry in value.split(';').map(str::trim).filter(|e| !e.is_empty()) {
        let (name, rest) = entry
            .split_once('(')
            .ok_or_else(|| err(format!("entry `{entry}`: expected `segment (x, y[, z])`")))?;
        let i = segment_index(key, value, name.trim())?;
        let (inside, _comment) = rest
            .split_once(')')
            .ok_or_else(|| err(format!("entry `{entry}`: missing `)`")))?;
        let parts: Vec<&str> = inside.split(',').collect();
        if !(2..=3).contains(&parts.len()) {
            return Err(err(format!(
                "entry `{entry}`: expected 2 or 3 coordinates, found {}",
                parts.len()
            )));
        }
        let mut r = [0.0; 3];
        for (k, p) in parts.iter().enumerate() {
            r[k] = number(key, value, p)?;
        }
        if out[i].replace(r).is_some() {
            return Err(err(format!("segment `{}` given twice", SEGMENTS[i])));
        }
    }
    Ok(out)
}

/// Formats IMU positions as an `imu_mounts_m` value (millimetre resolution).
pub fn format_imu_mounts(positions: &[[f64; 3]; 4]) -> String {
    SEGMENTS
        .iter()
        .zip(positions.iter())
        .map(|(s, r)| format!("{s} ({:+.4}, {:+.4}, {:+.4})", r[0], r[1], r[2]))
        .collect::<Vec<_>>()
        .join("; ")
}

/// Parses a `segment_lengths_m` value: `(thigh, shank)`.
pub fn parse_segment_lengths(value: &str) -> Result<(Option<f64>, Option<f64>), BodyMetaError> {
    let key = SEGMENT_LENGTHS_KEY;
    let mut out = (None, None);
    for entry in value.split(';').map(str::trim).filter(|e| !e.is_empty()) {
        let mut words = entry.split_whitespace();
        let (Some(name), Some(v), None) = (words.next(), words.next(), words.next()) else {
            return Err(BodyMetaError {
                key,
                value: value.to_string(),
                problem: format!("entry `{entry}`: expected `thigh LENGTH` or `shank LENGTH`"),
            });
        };
        let v = number(key, value, v)?;
        match segment_index(key, value, name)? {
            1 => out.0 = Some(v),
            2 => out.1 = Some(v),
            _ => {
                return Err(BodyMetaError {
                    key,
                    value: value.to_string(),
                    problem: format!("`{name}`: only thigh and shank lengths are used"),
                })
            }
        }
    }
    Ok(out)
}

/// Formats `(thigh, shank)` as a `segment_lengths_m` value.
pub fn format_segment_lengths(thigh: f64, shank: f64) -> String {
    format!("thigh {thigh:.4}; shank {shank:.4}")
}

/// A length stated in free text as `LABEL NUMBER UNIT` (or `LABEL:` /
/// `LABEL =` before the number; unit `m`, `cm` or `mm`; case-insensitive),
/// in metres: the text is cut into clauses at
/// `,` `;` `(` `)`, and the clause must start with `label`, so that
/// `height` does not match `sensor height 96.4 cm`. `None` when no clause
/// states it or the number is not finite and positive.
pub fn free_text_length(text: &str, label: &str) -> Option<f64> {
    let label = label.to_ascii_lowercase();
    text.split([',', ';', '(', ')']).find_map(|clause| {
        let clause = clause.trim().to_ascii_lowercase();
        let after = clause.strip_prefix(label.as_str())?;
        // `LABEL 96.4 cm`, `LABEL: 96.4 cm`, `LABEL = 96.4 cm`; not `LABELs`.
        if !after.starts_with(|c: char| c.is_whitespace() || c == ':' || c == '=') {
            return None;
        }
        let rest = after.trim_start();
        let rest = rest.strip_prefix([':', '=']).map_or(rest, str::trim_start);
        let end = rest
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(rest.len());
        // The unit as a decimal exponent, so that `96.4 cm` is the f64
        // nearest 0.964 (one correctly rounded parse, no division).
        let exponent = match rest[end..].split_whitespace().next()? {
            "m" => 0,
            "cm" => -2,
            "mm" => -3,
            _ => return None,
        };
        let value: f64 = format!("{}e{exponent}", &rest[..end]).parse().ok()?;
        Some(value).filter(|v| v.is_finite() && *v > 0.0)
    })
}

/// A length the trial's `# subject:` line states ([`free_text_length`]).
pub fn subject_length(meta: &TrialMeta, label: &str) -> Option<f64> {
    meta.get(SUBJECT_KEY)
        .and_then(|text| free_text_length(text, label))
}

impl TrialMeta {
    /// The body geometry this trial's metadata states (docs/CHAIN.md).
    pub fn body(&self) -> Result<BodyMeta, BodyMetaError> {
        let mut b = BodyMeta::default();
        if let Some(v) = self.get(IMU_MOUNTS_KEY) {
            b.imu_position = parse_imu_mounts(v)?;
        }
        if let Some(v) = self.get(SEGMENT_LENGTHS_KEY) {
            (b.thigh_length, b.shank_length) = parse_segment_lengths(v)?;
        }
        b.height = self.body_height()?;
        Ok(b)
    }

    /// The body height `# height_m:` alone (`None` when absent), for a
    /// method that reads no other geometry: it does not fail on an
    /// `imu_mounts_m` it does not use (an audit, session 31:
    /// `lowback-speed` on a trial stating its mounts in words).
    pub fn body_height(&self) -> Result<Option<f64>, BodyMetaError> {
        self.get(HEIGHT_KEY)
            .map(|v| number(HEIGHT_KEY, v, v))
            .transpose()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mounts_parse_with_two_or_three_coordinates_and_trailing_comments() {
        let v = "trunk (-0.080, +0.100); thigh (+0.000, -0.215, 0.08); foot (+0.080, -0.010) in segment frames (origin ankle)";
        let m = parse_imu_mounts(v).unwrap();
        assert_eq!(m[0], Some([-0.08, 0.1, 0.0]));
        assert_eq!(m[1], Some([0.0, -0.215, 0.08]));
        assert_eq!(m[2], None);
        assert_eq!(m[3], Some([0.08, -0.01, 0.0]));
    }

    #[test]
    fn formatted_geometry_reads_back() {
        let p = [
            [-0.1, 0.08, -0.09],
            [0.0, -0.2144, 0.08],
            [0.0, -0.2153, 0.05],
            [0.07, -0.005, 0.0],
        ];
        let back = parse_imu_mounts(&format_imu_mounts(&p)).unwrap();
        for i in 0..4 {
            let b = back[i].unwrap();
            for k in 0..3 {
                assert!((b[k] - p[i][k]).abs() < 5e-5);
            }
        }
        assert_eq!(
            parse_segment_lengths(&format_segment_lengths(0.42875, 0.4305)).unwrap(),
            (Some(0.4288), Some(0.4305))
        );
    }

    /// The HA001 files of `mobgap-lowerback` state the body and sensor
    /// heights only in their `# subject:` line.
    #[test]
    fn lengths_in_free_text_are_read_by_their_clause() {
        let text =
            "healthy adult (HA/001), height 159 cm, weight 73 kg, sensor height 96.4 cm; Test5";
        assert_eq!(free_text_length(text, "height"), Some(1.59));
        assert_eq!(free_text_length(text, "sensor height"), Some(0.964));
        assert_eq!(free_text_length("Height 1.75 m", "height"), Some(1.75));
        assert_eq!(
            free_text_length("sensor height 964mm", "sensor height"),
            Some(0.964)
        );
        assert_eq!(free_text_length("sensor height 96.4 cm", "height"), None);
        assert_eq!(
            free_text_length("sensor height: 96.4 cm", "sensor height"),
            Some(0.964)
        );
        assert_eq!(free_text_length("height = 1.59 m", "height"), Some(1.59));
        assert_eq!(free_text_length("height:159cm", "height"), Some(1.59));
        assert_eq!(free_text_length("heights: 159 cm", "height"), None);
        assert_eq!(free_text_length("heights 159 cm", "height"), None);
        assert_eq!(free_text_length("height 159 inches", "height"), None);
        assert_eq!(free_text_length("height unknown", "height"), None);
        assert_eq!(free_text_length("height 0 cm", "height"), None);
        assert_eq!(free_text_length("height", "height"), None);
        let mut meta = TrialMeta::new();
        assert_eq!(subject_length(&meta, "height"), None);
        meta.set(SUBJECT_KEY, "adult, height 180 cm");
        assert_eq!(subject_length(&meta, "height"), Some(1.8));
    }

    #[test]
    fn bad_entries_name_the_key_and_the_problem() {
        let e = parse_imu_mounts("knee (0, 1)").unwrap_err().to_string();
        assert!(
            e.contains("imu_mounts_m") && e.contains("unknown segment `knee`"),
            "{e}"
        );
        let e = parse_imu_mounts("thigh (0, x)").unwrap_err().to_string();
        assert!(e.contains("`x` is not a finite number"), "{e}");
        let e = parse_imu_mounts("thigh (0)").unwrap_err().to_string();
        assert!(e.contains("2 or 3 coordinates"), "{e}");
        let e = parse_segment_lengths("thigh").unwrap_err().to_string();
        assert!(e.contains("segment_lengths_m"), "{e}");
        let mut meta = TrialMeta::new();
        meta.set("height_m", "tall");
        assert!(meta.body().unwrap_err().to_string().contains("height_m"));
    }
}
