//! Gait-library files (paper 003): a B-SLIP gait library as versioned JSON.
//!
//! Format `limbfuse-gait-library`, version 1 (docs/GAIT_IMM.md):
//!
//! ```text
//! { "format": "limbfuse-gait-library", "version": 1,
//!   "body": { "mass": kg, "rest_length": m, "gravity": m/s^2 },
//!   "search": { "k_max": N/m, "stiffness_weight": m^2, "periodic_tol": .. },
//!   "gaits": [ { "speed": m/s,
//!       "xi": { "phi": rad, "theta": rad, "stiffness": N/m, "height": m,
//!               "lateral": m, "forward_speed": m/s },
//!       "rest_length": m, "step_length": m, "step_width": m, "step_time": s,
//!       "t_touchdown": s, "t_lift_off": s, "periodicity_residual": ..,
//!       "vertical_excursion": m, "lateral_excursion": m,
//!       "trajectory": { "SS1": [[t, x, y, z, vx, vy, vz], ...], "DS": [...], "SS2": [...] } } ] }
//! ```
//!
//! Trajectories are one step from MS (trailing foot at the origin, left
//! foot trailing), world axes of SPEC section 1. The reader checks the format
//! name and version before anything else, and names the file, line and
//! column of a syntax error (e.g. a truncated file).

use std::path::{Path, PathBuf};

use limbfuse_models::bslip::{BslipParams, GaitParameters, GaitTemplate};
use serde::{Deserialize, Serialize};

/// Format name in the `format` field.
pub const FORMAT: &str = "limbfuse-gait-library";
/// Version this build reads and writes.
pub const VERSION: u32 = 1;

/// A problem with a gait-library file.
#[derive(Debug, thiserror::Error)]
pub enum LibraryFileError {
    /// The file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// File path.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// Not valid JSON (e.g. truncated).
    #[error("{}:{line}:{column}: not a valid gait-library file: {message}", path.display())]
    Syntax {
        /// File path.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What the parser found.
        message: String,
    },
    /// Wrong format name or version.
    #[error("{}: {message}", path.display())]
    Version {
        /// File path.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// Valid JSON with missing or invalid content.
    #[error("{}: {message}", path.display())]
    Content {
        /// File path.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

/// Body parameters shared by the library's gaits.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BodyRecord {
    /// Mass (kg).
    pub mass: f64,
    /// Leg rest length (m).
    pub rest_length: f64,
    /// Gravity (m/s^2).
    pub gravity: f64,
}

/// Search settings the library was built with.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SearchRecord {
    /// `k_max` (N/m).
    pub k_max: f64,
    /// Weight of the stiffness term (m^2).
    pub stiffness_weight: f64,
    /// Periodicity tolerance (m, m/s).
    pub periodic_tol: f64,
}

/// Gait parameters `xi`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct XiRecord {
    /// Sagittal touchdown angle (rad).
    pub phi: f64,
    /// Lateral touchdown angle (rad).
    pub theta: f64,
    /// Stiffness (N/m).
    pub stiffness: f64,
    /// CoM height at MS (m).
    pub height: f64,
    /// Lateral CoM offset from the stance foot at MS (m).
    pub lateral: f64,
    /// Forward velocity at MS (m/s).
    pub forward_speed: f64,
}

/// Sampled trajectory rows `[t, x, y, z, vx, vy, vz]` per phase.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct PhaseTrajectories {
    /// First single support.
    #[serde(rename = "SS1")]
    pub ss1: Vec<[f64; 7]>,
    /// Double support.
    #[serde(rename = "DS")]
    pub ds: Vec<[f64; 7]>,
    /// Second single support.
    #[serde(rename = "SS2")]
    pub ss2: Vec<[f64; 7]>,
}

/// One gait of the file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GaitRecord {
    /// Mean forward speed (m/s).
    pub speed: f64,
    /// Gait parameters.
    pub xi: XiRecord,
    /// Leg rest length of this gait (m) (differs from the body's after rescaling).
    pub rest_length: f64,
    /// Step length (m).
    pub step_length: f64,
    /// Step width (m).
    pub step_width: f64,
    /// Step duration (s).
    pub step_time: f64,
    /// Touchdown time after MS (s).
    pub t_touchdown: f64,
    /// Lift-off time after MS (s).
    pub t_lift_off: f64,
    /// Largest periodicity residual (m, m/s).
    pub periodicity_residual: f64,
    /// Peak-to-peak vertical CoM excursion over a step (m).
    pub vertical_excursion: f64,
    /// Peak-to-peak lateral CoM excursion over a stride (m).
    pub lateral_excursion: f64,
    /// Sampled trajectories.
    pub trajectory: PhaseTrajectories,
}

/// A gait library file's content.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GaitLibraryFile {
    /// Always [`FORMAT`].
    pub format: String,
    /// Always [`VERSION`] when written by this build.
    pub version: u32,
    /// Body parameters.
    pub body: BodyRecord,
    /// Search settings.
    pub search: SearchRecord,
    /// Gaits, by increasing speed.
    pub gaits: Vec<GaitRecord>,
}

impl GaitRecord {
    /// The template the IMM uses.
    pub fn template(&self, body: &BodyRecord) -> GaitTemplate {
        let x = self.xi;
        GaitTemplate {
            speed: self.speed,
            body: BslipParams {
                mass: body.mass,
                rest_length: self.rest_length,
                stiffness: x.stiffness,
                gravity: body.gravity,
            },
            gait: GaitParameters {
                phi: x.phi,
                theta: x.theta,
                stiffness: x.stiffness,
                height: x.height,
                lateral: x.lateral,
                forward_speed: x.forward_speed,
            },
            step_length: self.step_length,
            step_width: self.step_width,
            step_time: self.step_time,
            t_touchdown: self.t_touchdown,
            t_lift_off: self.t_lift_off,
        }
    }
}

impl GaitLibraryFile {
    /// The templates of all gaits, by increasing speed.
    pub fn templates(&self) -> Vec<GaitTemplate> {
        self.gaits.iter().map(|g| g.template(&self.body)).collect()
    }

    /// Writes the library as JSON ([`crate::AtomicFile`]: whole or not at all).
    pub fn write(&self, path: &Path) -> Result<(), LibraryFileError> {
        let text = serde_json::to_string(self).map_err(|e| LibraryFileError::Content {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        crate::AtomicFile::write(path, text).map_err(|source| LibraryFileError::Io {
            path: path.to_path_buf(),
            source,
        })
    }

    /// Reads and checks a library file.
    pub fn read(path: &Path) -> Result<Self, LibraryFileError> {
        let text = crate::bounded_text::read_text_at_most(
            path,
            crate::bounded_text::MAX_LIBRARY_FILE_BYTES,
            "a gait-library file (JSON, tens of MB at most)",
        )
        .map_err(|source| LibraryFileError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(path, &text)
    }

    /// Parses library text; `path` names it in errors.
    pub fn parse(path: &Path, text: &str) -> Result<Self, LibraryFileError> {
        let p = || path.to_path_buf();
        let syntax = |e: serde_json::Error| LibraryFileError::Syntax {
            path: p(),
            line: e.line(),
            column: e.column(),
            message: e.to_string(),
        };
        let value: serde_json::Value = serde_json::from_str(text).map_err(syntax)?;
        let format = value.get("format").and_then(|v| v.as_str());
        if format != Some(FORMAT) {
            return Err(LibraryFileError::Version {
                path: p(),
                message: format!(
                    "expected `\"format\": \"{FORMAT}\"`, found {}",
                    format.map_or("no format field".to_string(), |f| format!("`{f}`"))
                ),
            });
        }
        let version = value.get("version").and_then(|v| v.as_u64());
        if version != Some(u64::from(VERSION)) {
            return Err(LibraryFileError::Version {
                path: p(),
                message: format!(
                    "gait-library version {} is not supported by this build (reads version {VERSION}); rebuild the library with `limbfuse gait-library build`",
                    version.map_or("(missing)".to_string(), |v| v.to_string())
                ),
            });
        }
        // (the JSON path of a bad value: an audit found "invalid length 6,
        // expected an array of length 7" without which gait or row)
        let lib: GaitLibraryFile =
            serde_path_to_error::deserialize(value).map_err(|e| LibraryFileError::Content {
                path: p(),
                message: format!("at `{}`: {}", e.path(), e.inner()),
            })?;
        lib.validate(path)?;
        Ok(lib)
    }

    fn validate(&self, path: &Path) -> Result<(), LibraryFileError> {
        let bad = |message: String| LibraryFileError::Content {
            path: path.to_path_buf(),
            message,
        };
        let b = self.body;
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !(positive(b.mass) && positive(b.rest_length) && positive(b.gravity)) {
            return Err(bad(
                "body: mass, rest_length and gravity must be positive numbers".into(),
            ));
        }
        if self.gaits.is_empty() {
            return Err(bad("the library has no gaits".into()));
        }
        // (an audit: negative and repeated speeds were accepted, and the
        // continuous family interpolates between neighbours by speed)
        for (i, w) in self.gaits.windows(2).enumerate() {
            if w[1].speed.partial_cmp(&w[0].speed) != Some(core::cmp::Ordering::Greater) {
                return Err(bad(format!(
                    "gait {} (speed {} m/s) after gait {i} ({} m/s): gaits must be listed by \
                     increasing speed, each speed once (as `limbfuse gait-library build` writes them)",
                    i + 1,
                    w[1].speed,
                    w[0].speed
                )));
            }
        }
        for (i, g) in self.gaits.iter().enumerate() {
            if g.speed.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
                return Err(bad(format!(
                    "gait {i}: speed {} m/s: expected a positive walking speed",
                    g.speed
                )));
            }
            let x = g.xi;
            let values = [
                g.speed,
                x.phi,
                x.theta,
                x.stiffness,
                x.height,
                x.lateral,
                x.forward_speed,
                g.rest_length,
                g.step_length,
                g.step_width,
                g.step_time,
                g.t_touchdown,
                g.t_lift_off,
            ];
            if values.iter().any(|v| !v.is_finite())
                || !(x.stiffness > 0.0
                    && x.height > 0.0
                    && g.rest_length > 0.0
                    && g.step_time > 0.0)
                || !(0.0 < g.t_touchdown
                    && g.t_touchdown < g.t_lift_off
                    && g.t_lift_off < g.step_time)
            {
                return Err(bad(format!(
                    "gait {i} (speed {} m/s): parameters must be finite, stiffness/height/rest_length/step_time positive and 0 < t_touchdown < t_lift_off < step_time",
                    g.speed
                )));
            }
            // (an audit: empty SS1/DS/SS2 and all-zero times were accepted)
            // Each phase holds at least one row and its times do not fall,
            // and the step's times rise from its first row to its last. A
            // phase of one row is accepted: `gait-library build` before
            // 2026-12-06 wrote a phase shorter than its 10 ms sampling step
            // (a lift-off just before the end MS) as one row, and a library
            // limbfuse built must keep loading (the rows are not used by
            // the estimators).
            let t = &g.trajectory;
            let mut before: Option<f64> = None;
            for (phase, rows) in [("SS1", &t.ss1), ("DS", &t.ds), ("SS2", &t.ss2)] {
                let times_rise = rows.windows(2).all(|w| w[1][0] >= w[0][0])
                    && rows.first().zip(before).is_none_or(|(r, b)| r[0] >= b);
                if rows.is_empty() || rows.iter().flatten().any(|v| !v.is_finite()) || !times_rise {
                    return Err(bad(format!(
                        "`gaits[{i}].trajectory.{phase}` (speed {} m/s): expected finite rows \
                         [t, x, y, z, vx, vy, vz] with times that do not fall (from the previous \
                         phase's last on), found {}",
                        g.speed,
                        if rows.is_empty() {
                            "none"
                        } else if times_rise {
                            "a non-finite value"
                        } else {
                            "times that fall"
                        }
                    )));
                }
                before = rows.last().map(|r| r[0]);
            }
            let (first, last) = (t.ss1[0][0], t.ss2[t.ss2.len() - 1][0]);
            if last <= first {
                return Err(bad(format!(
                    "`gaits[{i}].trajectory` (speed {} m/s): expected the times to rise over the \
                     step, found {first} s to {last} s",
                    g.speed
                )));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> GaitLibraryFile {
        GaitLibraryFile {
            format: FORMAT.into(),
            version: VERSION,
            body: BodyRecord {
                mass: 80.0,
                rest_length: 1.0,
                gravity: 9.81,
            },
            search: SearchRecord {
                k_max: 6e4,
                stiffness_weight: 1e-2,
                periodic_tol: 1e-8,
            },
            gaits: vec![GaitRecord {
                speed: 0.7,
                xi: XiRecord {
                    phi: 1.2,
                    theta: 0.066,
                    stiffness: 15000.0,
                    height: 0.95,
                    lateral: 0.03,
                    forward_speed: 0.55,
                },
                rest_length: 1.0,
                step_length: 0.57,
                step_width: 0.11,
                step_time: 0.81,
                t_touchdown: 0.32,
                t_lift_off: 0.49,
                periodicity_residual: 1e-9,
                vertical_excursion: 0.03,
                lateral_excursion: 0.05,
                trajectory: PhaseTrajectories {
                    ss1: vec![[0.0; 7], [0.32, 0.2, 0.0, 0.95, 0.6, 0.0, 0.0]],
                    ds: vec![[0.32, 0.2, 0.0, 0.95, 0.6, 0.0, 0.0], [0.49; 7]],
                    ss2: vec![[0.49; 7], [0.81; 7]],
                },
            }],
        }
    }

    #[test]
    fn round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("lib.json");
        sample().write(&p).unwrap();
        assert_eq!(GaitLibraryFile::read(&p).unwrap(), sample());
    }

    #[test]
    fn truncated_file_names_line_and_column() {
        let text = serde_json::to_string_pretty(&sample()).unwrap();
        let cut = &text[..text.len() / 2];
        let e = GaitLibraryFile::parse(Path::new("lib.json"), cut).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, LibraryFileError::Syntax { .. }), "{msg}");
        assert!(msg.starts_with("lib.json:"), "{msg}");
        assert!(msg.contains("EOF"), "{msg}");
    }

    #[test]
    fn other_version_is_refused_with_the_versions_named() {
        let text = serde_json::to_string(&sample())
            .unwrap()
            .replace("\"version\":1", "\"version\":2");
        let e = GaitLibraryFile::parse(Path::new("lib.json"), &text).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, LibraryFileError::Version { .. }), "{msg}");
        assert!(
            msg.contains("version 2") && msg.contains("version 1"),
            "{msg}"
        );
        let e = GaitLibraryFile::parse(Path::new("x.json"), "{\"a\": 1}").unwrap_err();
        assert!(e.to_string().contains("format"), "{e}");
    }

    /// An audit shortened one row of a phase trajectory to 6 numbers: the
    /// message was "invalid length 6, expected an array of length 7" with
    /// no gait, phase or row. Now the JSON path of the value is named.
    #[test]
    fn a_bad_value_is_named_by_its_json_path() {
        let mut lib = sample();
        lib.gaits[0].trajectory.ds = vec![[0.0; 7], [0.0; 7]];
        let text = serde_json::to_string(&lib).unwrap().replacen(
            "[0.0,0.0,0.0,0.0,0.0,0.0,0.0]]",
            "[0.0,0.0,0.0,0.0,0.0,0.0]]",
            1,
        );
        let e = GaitLibraryFile::parse(Path::new("lib.json"), &text).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, LibraryFileError::Content { .. }), "{msg}");
        assert!(
            msg.contains("at `gaits[0].trajectory.DS[1]`")
                && msg.contains("invalid length 6, expected an array of length 7"),
            "{msg}"
        );
    }

    #[test]
    fn inconsistent_event_times_are_refused() {
        let mut lib = sample();
        lib.gaits[0].t_lift_off = 0.1;
        let text = serde_json::to_string(&lib).unwrap();
        let e = GaitLibraryFile::parse(Path::new("lib.json"), &text).unwrap_err();
        assert!(e.to_string().contains("gait 0"), "{e}");
    }

    #[test]
    fn speeds_must_be_positive_and_increasing() {
        let mut lib = sample();
        lib.gaits[0].speed = -0.7;
        let text = serde_json::to_string(&lib).unwrap();
        let e = GaitLibraryFile::parse(Path::new("lib.json"), &text).unwrap_err();
        assert!(e.to_string().contains("positive walking speed"), "{e}");
        let mut lib = sample();
        lib.gaits.push(lib.gaits[0].clone());
        let text = serde_json::to_string(&lib).unwrap();
        let e = GaitLibraryFile::parse(Path::new("lib.json"), &text).unwrap_err();
        assert!(
            e.to_string().contains("increasing speed, each speed once"),
            "{e}"
        );
    }

    /// An audit: a library with an empty `SS1`/`DS`/`SS2` trajectory or
    /// with all-zero trajectory times was accepted by `estimate --method
    /// imm-bslip` and `simulate bslip`. Now refused with the JSON path.
    #[test]
    fn empty_or_timeless_trajectories_are_refused_with_the_json_path() {
        let text = serde_json::to_string(&sample()).unwrap();
        assert!(GaitLibraryFile::parse(Path::new("lib.json"), &text).is_ok());
        let mut lib = sample();
        lib.gaits[0].trajectory.ds.clear();
        let text = serde_json::to_string(&lib).unwrap();
        let e = GaitLibraryFile::parse(Path::new("lib.json"), &text)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("lib.json") && e.contains("`gaits[0].trajectory.DS`"),
            "{e}"
        );
        let mut lib = sample();
        for row in &mut lib.gaits[0].trajectory.ss2 {
            row[0] = 0.0;
        }
        let text = serde_json::to_string(&lib).unwrap();
        let e = GaitLibraryFile::parse(Path::new("lib.json"), &text)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`gaits[0].trajectory.SS2`"), "{e}");
        let mut lib = sample();
        let t = &mut lib.gaits[0].trajectory;
        for phase in [&mut t.ss1, &mut t.ds, &mut t.ss2] {
            phase.truncate(1);
            phase[0][0] = 0.0;
        }
        let text = serde_json::to_string(&lib).unwrap();
        let e = GaitLibraryFile::parse(Path::new("lib.json"), &text)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`gaits[0].trajectory`") && e.contains("rise"),
            "{e}"
        );
    }

    /// `gait-library build` before 2026-12-06 wrote a phase shorter than
    /// its 10 ms sampling step as one row (a lift-off 4 ms before the end
    /// MS: `--speeds 0.45:0.85:0.1 --leg-length 0.95 --mass 70`, SS2 = the
    /// MS row alone), and the reader of 2026-12-05 refused that library;
    /// such a file must keep loading.
    #[test]
    fn a_one_row_phase_of_an_older_build_loads() {
        let mut lib = sample();
        lib.gaits[0].trajectory.ss2 = vec![[0.81; 7]];
        let text = serde_json::to_string(&lib).unwrap();
        let parsed = GaitLibraryFile::parse(Path::new("lib.json"), &text);
        assert!(parsed.is_ok(), "{:?}", parsed.err());
    }
}
