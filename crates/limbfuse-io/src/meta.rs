//! Trial metadata: the leading `# key: value` comment lines of a trial file.

use limbfuse_core::{SensorRanges, STANDARD_GRAVITY};

/// Trial metadata key of the gyroscopes' range (rad/s).
pub const GYRO_RANGE_KEY: &str = "gyro_range_rad_s";
/// Trial metadata key of the accelerometers' range (m/s^2).
pub const ACC_RANGE_KEY: &str = "acc_range_m_s2";

/// A sensor range entry of the metadata that is not a positive finite
/// number ([`TrialMeta::sensor_ranges`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BadSensorRange {
    /// The metadata key ([`GYRO_RANGE_KEY`] or [`ACC_RANGE_KEY`]).
    pub key: &'static str,
    /// Its value.
    pub found: String,
}

/// Ordered `key: value` metadata of a trial. Unknown keys are kept.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TrialMeta {
    entries: Vec<(String, String)>,
}

impl TrialMeta {
    /// Empty metadata.
    pub fn new() -> Self {
        Self::default()
    }

    /// Metadata starting with `format: limbfuse-trial/1`.
    pub fn trial_v1() -> Self {
        let mut m = Self::new();
        m.set("format", "limbfuse-trial/1");
        m
    }

    /// Sets `key` (replacing an earlier value, keeping its position).
    pub fn set(&mut self, key: impl Into<String>, value: impl ToString) {
        let key = key.into();
        let value = value.to_string();
        match self.entries.iter_mut().find(|(k, _)| *k == key) {
            Some(e) => e.1 = value,
            None => self.entries.push((key, value)),
        }
    }

    /// Value of `key`, if present.
    pub fn get(&self, key: &str) -> Option<&str> {
        self.entries
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// All entries in file order.
    pub fn entries(&self) -> &[(String, String)] {
        &self.entries
    }

    /// The side of the trial's single-leg columns: its `leg` entry (`left`
    /// or `right`), right when absent (SPEC section 2). The error says what
    /// the entry holds and what was expected; the caller adds the file.
    pub fn leg(&self) -> Result<limbfuse_core::Side, String> {
        match self.get("leg") {
            None => Ok(limbfuse_core::Side::Right),
            Some(text) => limbfuse_core::Side::parse(text)
                .ok_or_else(|| format!("metadata `# leg: {text}`: expected `left` or `right`")),
        }
    }

    /// Gravity (m/s^2): the `g` entry, 9.81 without one. An entry that is
    /// not a positive finite number is an error naming it (an audit found
    /// `# g: abc`, `0`, `-9.81` and `nan` silently taken for 9.81).
    pub fn gravity(&self) -> Result<f64, String> {
        match self.get("g") {
            None => Ok(STANDARD_GRAVITY),
            Some(text) => text
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|g| g.is_finite() && *g > 0.0)
                .ok_or_else(|| {
                    format!(
                        "metadata `# g: {text}`: expected gravity in m/s^2, a positive number \
                         (e.g. 9.81)"
                    )
                }),
        }
    }

    /// The stated sample rate (Hz): the `sample_rate_hz` entry, `None`
    /// without one. An entry that is not a positive finite number is an
    /// error naming it (an audit found `# sample_rate_hz: abc`, `nan`,
    /// `-100` and `0` taken for no rate by `estimate`, in CSV and Arrow
    /// trials alike).
    pub fn sample_rate_hz(&self) -> Result<Option<f64>, String> {
        match self.get("sample_rate_hz") {
            None => Ok(None),
            Some(text) => text
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|hz| hz.is_finite() && *hz > 0.0)
                .map(Some)
                .ok_or_else(|| {
                    format!(
                        "metadata `# sample_rate_hz: {text}`: expected the sample rate in Hz, \
                         a positive number (e.g. 100)"
                    )
                }),
        }
    }

    /// The sensor ranges of the trial: its `gyro_range_rad_s` and
    /// `acc_range_m_s2` entries where given, the datasheet defaults of
    /// [`SensorRanges::default`] otherwise. A gyroscope range given is the
    /// sensor's full scale: readings beyond it are out of range, readings at
    /// it are clipped.
    pub fn sensor_ranges(&self) -> Result<SensorRanges, BadSensorRange> {
        let mut r = SensorRanges::default();
        for (key, slot) in [
            (GYRO_RANGE_KEY, &mut r.gyro_rad_s),
            (ACC_RANGE_KEY, &mut r.acc_m_s2),
        ] {
            if let Some(text) = self.get(key) {
                match text.trim().parse::<f64>() {
                    Ok(v) if v.is_finite() && v > 0.0 => *slot = v,
                    _ => {
                        return Err(BadSensorRange {
                            key,
                            found: text.to_string(),
                        })
                    }
                }
            }
        }
        if self.get(GYRO_RANGE_KEY).is_some() {
            r.gyro_full_scale_rad_s = Some(r.gyro_rad_s);
        }
        if self.get(ACC_RANGE_KEY).is_some() {
            r.acc_full_scale_m_s2 = Some(r.acc_m_s2);
        }
        Ok(r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_core::Side;

    /// `# g:` that is not a positive finite number is an error naming the
    /// line (it was taken for 9.81 with nothing said); absent, 9.81.
    #[test]
    fn sample_rate_is_the_line_or_an_error() {
        let mut m = TrialMeta::trial_v1();
        assert_eq!(m.sample_rate_hz(), Ok(None));
        m.set("sample_rate_hz", " 50 ");
        assert_eq!(m.sample_rate_hz(), Ok(Some(50.0)));
        for bad in ["abc", "0", "-100", "nan", "inf", ""] {
            m.set("sample_rate_hz", bad);
            let e = m.sample_rate_hz().unwrap_err();
            assert!(e.contains(&format!("`# sample_rate_hz: {bad}`")), "{e}");
        }
    }

    #[test]
    fn gravity_is_the_g_line_or_an_error() {
        let mut m = TrialMeta::trial_v1();
        assert_eq!(m.gravity(), Ok(STANDARD_GRAVITY));
        m.set("g", " 9.5 ");
        assert_eq!(m.gravity(), Ok(9.5));
        for bad in ["abc", "0", "-9.81", "nan", "inf", ""] {
            m.set("g", bad);
            let e = m.gravity().unwrap_err();
            assert!(e.contains(&format!("`# g: {bad}`")), "{e}");
        }
    }

    /// The ranges are the entries given, the defaults otherwise; a gyro
    /// range given is the full scale; a bad entry names its key and value.
    #[test]
    fn sensor_ranges_come_from_the_entries() {
        let mut m = TrialMeta::trial_v1();
        assert_eq!(m.sensor_ranges(), Ok(SensorRanges::default()));
        m.set(GYRO_RANGE_KEY, " 17.5 ");
        m.set(ACC_RANGE_KEY, "80");
        let r = m.sensor_ranges().unwrap();
        assert_eq!(
            (
                r.gyro_rad_s,
                r.acc_m_s2,
                r.gyro_full_scale_rad_s,
                r.acc_full_scale_m_s2
            ),
            (17.5, 80.0, Some(17.5), Some(80.0))
        );
        for bad in ["abc", "0", "-1", "nan", "inf"] {
            m.set(ACC_RANGE_KEY, bad);
            assert_eq!(
                m.sensor_ranges(),
                Err(BadSensorRange {
                    key: ACC_RANGE_KEY,
                    found: bad.to_string()
                })
            );
        }
    }

    #[test]
    fn leg_is_right_when_absent_and_named_when_wrong() {
        let mut m = TrialMeta::trial_v1();
        assert_eq!(m.leg(), Ok(Side::Right));
        m.set("leg", "left");
        assert_eq!(m.leg(), Ok(Side::Left));
        m.set("leg", "both");
        assert_eq!(
            m.leg(),
            Err("metadata `# leg: both`: expected `left` or `right`".to_string())
        );
    }
}
