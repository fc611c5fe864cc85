//! What `limbfuse evaluate` says beside its numbers: the notes of an angle
//! [`Evaluation`] (offset-free, synchronisation lags, channels left out of
//! the mean, the knee's zero, AR/AGR, missing inputs) and of its trial
//! (`align`'s assumed zero). One text for `evaluate`'s table and for the
//! report's (`limbfuse-report`), which lists them beside the same numbers.

use limbfuse_core::sample::AngleChannel;
use limbfuse_io::TrialMeta;

use crate::metrics::Evaluation;

impl Evaluation {
    /// Every note of [`Evaluation::to_text`], in its order, one sentence
    /// each without a line end: what `evaluate` prints around its table.
    pub fn notes(&self) -> Vec<String> {
        let mut notes: Vec<String> = [self.offset_free_note(), self.sync_lag_note()]
            .into_iter()
            .flatten()
            .collect();
        if self.mean_rmse().is_some() {
            notes.extend(
                self.exact_channels_phrase()
                    .map(|p| format!("mean RMSE {p}")),
            );
        }
        notes.extend(self.knee_zero_note().map(|n| format!("note: {n}")));
        notes.extend(self.rate_notes());
        notes
    }

    /// With `--offset-free`: what is and is not offset-free.
    pub(crate) fn offset_free_note(&self) -> Option<String> {
        // (an audit: max|e| and mean e are not offset-free, and nothing
        // said so; RESULTS quotes them as they are)
        self.offset_free.then(|| {
            "offset-free: the mean error of each channel is removed before the RMSE; max|e| and mean e as measured, before the mean is removed".to_string()
        })
    }

    /// With `--max-lag`: the lag each channel was measured at.
    pub(crate) fn sync_lag_note(&self) -> Option<String> {
        let lags = self.sync_lag.as_ref()?;
        let list: Vec<String> = lags.iter().map(|(c, l)| format!("{c} {l:+}")).collect();
        Some(format!(
            "synchronised: each channel's estimate shifted by the lag (samples, + = estimate trails) that minimises its RMSE: {}",
            list.join(", ")
        ))
    }

    /// "without thigh: equal to the reference ...": the channels left out
    /// of the mean RMSE ([`Evaluation::exact_channels`]), `None` when none is.
    pub(crate) fn exact_channels_phrase(&self) -> Option<String> {
        let exact: Vec<&str> = self.exact_channels().iter().map(|c| c.name()).collect();
        (!exact.is_empty()).then(|| {
            format!(
                "without {}: equal to the reference on every sample to 1e-6 rad, a value the estimator was given",
                exact.join(", ")
            )
        })
    }

    /// A knee-axis estimate whose accelerometer angle set the zero in under
    /// half of the samples (`acc_trusted` of knee-selfalign,
    /// `inclination_used` of knee-gyro-axis): elsewhere its zero is the
    /// high-pass's, the trial mean, so the mean error there is that zero,
    /// not the estimator's shape (the knee rig: 3 % and 0 %, mean error
    /// -9.4 deg, offset-free 2.2). Not said when offset-free already.
    pub(crate) fn knee_zero_note(&self) -> Option<String> {
        let knee = AngleChannel::Joint(limbfuse_core::Joint::Knee);
        let evaluated = self.channels.iter().any(|(c, st)| *c == knee && st.n() > 0);
        if self.offset_free || !evaluated {
            return None;
        }
        let (name, used) = ["acc_trusted", "inclination_used"]
            .into_iter()
            .find_map(|n| self.diag_mean.get(n).map(|v| (n, *v)))?;
        (used < 0.5).then(|| {
            format!(
                "the accelerometer angle set the knee angle's zero in {:.0} % of the samples (`diag_{name}`); elsewhere the zero is the high-pass's (the trial mean), so the mean error is largely that zero: `--offset-free` compares the shape",
                100.0 * used
            )
        })
    }

    /// AR, AGR and the samples with a missing input, when the estimate has
    /// the diagnostics they count.
    pub(crate) fn rate_notes(&self) -> Vec<String> {
        let mut s = Vec::new();
        if let Some(ar) = self.accel_reliability_pct {
            s.push(format!(
                "accelerometer reliability AR: {ar:.1} % of samples"
            ));
        }
        if let Some(agr) = self.accel_global_reliability_pct {
            s.push(format!(
                "coupled accelerometer reliability AGR: {agr:.1} % of samples"
            ));
        }
        if let Some(m) = self.missing_input_pct {
            s.push(format!(
                "samples with a missing input (predicted without its update): {m:.1} %"
            ));
        }
        s
    }
}

/// The segments whose zero angle `align` set from an assumed mean angle
/// over walking (`<segment>_align_zero: mean-inclination ...`), not from
/// quiet standing (issue 17 item 6: a 9-10 deg error on every segment
/// without a word why).
pub fn segments_zeroed_by_assumption(meta: &TrialMeta) -> Vec<&'static str> {
    limbfuse_core::Segment::ALL
        .iter()
        .map(|s| s.name())
        .filter(|name| {
            meta.get(&format!("{name}_align_zero"))
                .is_some_and(|z| z.starts_with("mean-inclination"))
        })
        .collect()
}

/// `evaluate`'s note on a trial whose segment zeros `align` assumed
/// ([`segments_zeroed_by_assumption`]), without its `note: `; `None` when
/// there are none or the errors are offset-free (which removes it).
pub fn assumed_zero_note(meta: &TrialMeta, offset_free: bool) -> Option<String> {
    let zeroed = segments_zeroed_by_assumption(meta);
    (!offset_free && !zeroed.is_empty()).then(|| {
        format!(
            "`align` found no quiet standing and set the zero of {} from an assumed mean angle over the walking \
             data (0 deg unless `align --mean-angle SEGMENT=DEG` gave it): their absolute errors include how far the true mean is from that assumption; `--offset-free` scores without it",
            zeroed.join(", ")
        )
    })
}
