//! Every method `--method` accepts, by name. [`MethodName::parse`] is the one
//! place in limbfuse where a method name is compared with a string; every
//! other decision is a `match` on [`MethodName`].

use core::fmt;

/// An estimation method, by name (SPEC section 4, `--method`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum MethodName {
    /// Baseline: integration of each aligned gyro's sagittal rate.
    GyroIntegration,
    /// Baseline: inclination from each accelerometer.
    AccelInclination,
    /// Papers 000/001: per-segment error-state Kalman filters.
    Local,
    /// Papers 000/001: Markov-jump Kalman filter.
    Mjls,
    /// Paper 001: matricial global Kalman filter.
    Global,
    /// Paper 002: self-aligning knee angle.
    KneeSelfAlign,
    /// Paper 004: state-dependent Riccati equation filter.
    Sdre,
    /// Paper 004: extended Kalman(-Bucy) filter.
    Ekf,
    /// Paper 004: rotation-matrix (Mahony) knee.
    Rmx,
    /// Paper 003: interacting multiple models over a B-SLIP gait library.
    ImmBslip,
}

/// What a user needs to know about a method before running it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MethodInfo {
    /// The `--method` name.
    pub name: &'static str,
    /// One line: paper and what it estimates.
    pub summary: &'static str,
    /// The trial columns it reads.
    pub inputs: &'static str,
    /// What its parameter file (`--params`) and flags set.
    pub settings: &'static str,
    /// Whether `limbfuse demo` runs it on the walking trial.
    pub in_walking_demo: bool,
}

impl MethodName {
    /// Every method, in the order `limbfuse methods` lists them.
    pub const ALL: [MethodName; 10] = [
        MethodName::GyroIntegration,
        MethodName::AccelInclination,
        MethodName::Local,
        MethodName::Mjls,
        MethodName::Global,
        MethodName::KneeSelfAlign,
        MethodName::Sdre,
        MethodName::Ekf,
        MethodName::Rmx,
        MethodName::ImmBslip,
    ];

    /// The `--method` name.
    pub const fn name(self) -> &'static str {
        self.info().name
    }

    /// The method's description.
    pub const fn info(self) -> MethodInfo {
        const fn info(
            name: &'static str,
            summary: &'static str,
            inputs: &'static str,
            settings: &'static str,
            in_walking_demo: bool,
        ) -> MethodInfo {
            MethodInfo {
                name,
                summary,
                inputs,
                settings,
                in_walking_demo,
            }
        }
        match self {
            MethodName::GyroIntegration => info(
                "gyro-integration",
                "baseline: trapezoidal integration of each aligned gyro's z rate",
                "each segment's gyro (aligned: z = sagittal axis)",
                "none",
                true,
            ),
            MethodName::AccelInclination => info(
                "accel-inclination",
                "baseline: theta = atan2(acc_x, acc_y) per segment",
                "each segment's accelerometer (aligned)",
                "none",
                true,
            ),
            MethodName::Local => info(
                "local",
                "papers 000/001: per-segment error-state KFs (matricial local)",
                "the four IMUs (aligned)",
                "segment-filter parameter file (docs/TUNING.md): preset, noise densities, gates",
                true,
            ),
            MethodName::Mjls => info(
                "mjls",
                "papers 000/001: Markov-jump KF, 4 IMUs + 3 encoders",
                "the four IMUs (aligned) and the hip, knee and ankle encoders",
                "segment-filter parameter file (docs/TUNING.md); encoder_sigma, when_unreliable",
                true,
            ),
            MethodName::Global => info(
                "global",
                "paper 001: matricial global KF, 4 IMUs + relative rows + encoders",
                "the four IMUs (aligned); encoders when present",
                "segment-filter parameter file (docs/TUNING.md); relative_sigma, min_reliable",
                true,
            ),
            MethodName::KneeSelfAlign => info(
                "knee-selfalign",
                "paper 002: knee angle from raw thigh + shank IMUs, self-identified joint axis and position",
                "raw thigh and shank IMUs (any mounting)",
                "window, order, zero (file keys or --window/--order)",
                false,
            ),
            MethodName::Sdre => info(
                "sdre",
                "paper 004: SDRE estimator on the trial's model (knee-fes or fixed-hip metadata)",
                "thigh and shank IMUs, stimulation (and motor) columns; `# model:` metadata",
                "[model] parameter overrides, [tuning] q, s, a, p0, max_substep",
                false,
            ),
            MethodName::Ekf => info(
                "ekf",
                "paper 004: extended Kalman(-Bucy) filter on the trial's model",
                "thigh and shank IMUs, stimulation (and motor) columns; `# model:` metadata",
                "[model] parameter overrides, [tuning] q, s, a, p0, max_substep",
                false,
            ),
            MethodName::Rmx => info(
                "rmx",
                "paper 004: knee from the relative orientation of thigh and shank IMUs",
                "thigh and shank IMUs",
                "[rmx] kp, ki (Mahony gains)",
                false,
            ),
            MethodName::ImmBslip => info(
                "imm-bslip",
                "paper 003: gait phase and speed from CoM measurements, IMM over a B-SLIP gait library (--library)",
                "com_meas_x/y/z (and com_meas_vx/vy when present)",
                "library, kappa, rescale_height, weights, touchdown (file keys or --library, --kappa, ...)",
                false,
            ),
        }
    }

    /// Parses a `--method` name (or a file's `method` / `# method:` value).
    pub fn parse(text: &str) -> Result<MethodName, UnknownMethod> {
        let text = text.trim();
        Self::ALL
            .into_iter()
            .find(|m| m.name() == text)
            .ok_or_else(|| UnknownMethod(text.to_string()))
    }

    /// The segment-angle filters of papers 000/001 (`local`, `mjls`, `global`).
    pub const fn is_segment_filter(self) -> bool {
        matches!(
            self,
            MethodName::Local | MethodName::Mjls | MethodName::Global
        )
    }

    /// Whether the method's diagnostics include coupled relative rows
    /// (`upd_hip`, `upd_knee`, `upd_ankle` of the global filter's relative
    /// accelerometer rows, 001 eq 21), counted by the AGR of `evaluate`.
    pub const fn has_relative_rows(self) -> bool {
        matches!(self, MethodName::Global)
    }

    /// The methods `limbfuse demo` runs on its walking trial.
    pub fn walking_demo() -> impl Iterator<Item = MethodName> {
        Self::ALL.into_iter().filter(|m| m.info().in_walking_demo)
    }

    /// Every name, comma-separated (for messages).
    pub fn list() -> String {
        Self::ALL.map(MethodName::name).join(", ")
    }
}

impl fmt::Display for MethodName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl core::str::FromStr for MethodName {
    type Err = UnknownMethod;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        MethodName::parse(s)
    }
}

impl<'de> serde::Deserialize<'de> for MethodName {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        MethodName::parse(&s).map_err(serde::de::Error::custom)
    }
}

/// A method name limbfuse does not know.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown method `{0}`; available methods: {list}", list = MethodName::list())]
pub struct UnknownMethod(pub String);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_parses_back_and_is_unique() {
        for m in MethodName::ALL {
            assert_eq!(MethodName::parse(m.name()), Ok(m));
        }
        let mut names: Vec<_> = MethodName::ALL.map(MethodName::name).to_vec();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), MethodName::ALL.len());
    }

    #[test]
    fn unknown_names_list_the_available_ones() {
        let e = MethodName::parse("magic").unwrap_err().to_string();
        assert!(e.contains("unknown method `magic`") && e.contains("gyro-integration"));
    }
}
