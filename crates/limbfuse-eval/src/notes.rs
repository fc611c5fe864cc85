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
        notes.extend(self.coverage_note().map(|n| format!("note: {n}")));
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

    /// The channels scored on fewer rows than have a reference
    /// ([`Evaluation::coverage`]), `None` when every carried channel was
    /// scored wherever it has one. Their RMSE and the mean over channels
    /// cover the scored rows only, so two methods' figures on one trial may
    /// cover different rows (the segment filters wait up to 2 s for their
    /// start: docs/SEGMENT_FILTERS.md; `chain` 1 s).
    pub(crate) fn coverage_note(&self) -> Option<String> {
        // channels with the same counts in one group: "thigh, knee 156 of 311"
        let mut groups: Vec<((u64, u64), Vec<&str>)> = Vec::new();
        for c in self.coverage.iter().filter(|c| c.scored < c.with_reference) {
            let key = (c.scored, c.with_reference);
            match groups.iter_mut().find(|(k, _)| *k == key) {
                Some((_, names)) => names.push(c.channel.name()),
                None => groups.push((key, vec![c.channel.name()])),
            }
        }
        let short: Vec<String> = groups
            .iter()
            .map(|((n, of), names)| format!("{} {n} of {of}", names.join(", ")))
            .collect();
        (!short.is_empty()).then(|| {
            format!(
                "scored on fewer rows than have a reference ({}): the estimate is empty on the others \
                 (before the method has started, after a restart or without its inputs), and the RMSE \
                 and the mean cover the scored rows only (a `--window` that begins after every start scores \
                 each method on the same rows)",
                short.join(", ")
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

#[cfg(test)]
mod tests {
    use limbfuse_core::{Estimate, Record, Segment};

    use crate::{AngleMetrics, ChannelCoverage, EvalOptions};

    use super::*;

    /// Thigh and shank referenced on four rows; the thigh estimated on the
    /// last two only (a filter that started late), the shank on all, the
    /// foot carried but never estimated and without a reference.
    fn late_thigh(carried: Option<[bool; 7]>) -> Evaluation {
        let mut m = AngleMetrics::new("local", EvalOptions::default());
        if let Some(c) = carried {
            m.set_carried_channels(c);
        }
        for k in 0..4 {
            let mut r = Record::default();
            r.reference.segment[1] = Some(0.1);
            r.reference.segment[2] = Some(0.2);
            let mut e = Estimate::empty(0.01 * k as f64);
            e.segment[1] = (k >= 2).then_some(0.11);
            e.segment[2] = Some(0.2);
            m.push(&r, &e);
        }
        m.evaluation()
    }

    #[test]
    fn a_channel_scored_on_fewer_rows_than_its_reference_is_named() {
        let ev = late_thigh(Some([false, true, true, true, false, false, false]));
        let thigh = AngleChannel::Segment(Segment::Thigh);
        let shank = AngleChannel::Segment(Segment::Shank);
        assert_eq!(
            ev.coverage,
            vec![
                ChannelCoverage {
                    channel: thigh,
                    scored: 2,
                    with_reference: 4
                },
                ChannelCoverage {
                    channel: shank,
                    scored: 4,
                    with_reference: 4
                },
            ]
        );
        let note = ev.coverage_note().expect("a note");
        assert!(note.contains("(thigh 2 of 4)"), "{note}");
        assert!(ev.notes().iter().any(|n| n.contains("thigh 2 of 4")));
        assert!(ev.to_text().contains("note: scored on fewer rows"));
        let json = ev.to_json();
        assert_eq!(json["rows_scored"]["thigh"], 2);
        assert_eq!(json["rows_with_reference"]["thigh"], 4);
        assert_eq!(json["rows_scored"]["shank"], 4);
    }

    #[test]
    fn a_carried_channel_never_estimated_is_named_and_every_row_scored_is_silent() {
        // The thigh estimated on no row at all: named "0 of 4".
        let mut m = AngleMetrics::new("local", EvalOptions::default());
        m.set_carried_channels([true; 7]);
        let mut r = Record::default();
        r.reference.segment[1] = Some(0.1);
        r.reference.segment[2] = Some(0.2);
        let mut e = Estimate::empty(0.0);
        e.segment[2] = Some(0.2);
        for _ in 0..4 {
            m.push(&r, &e);
        }
        let note = m.evaluation().coverage_note().expect("a note");
        assert!(note.contains("(thigh 0 of 4)"), "{note}");
        // Without the carried channels, only the estimated ones count: the
        // thigh (estimated on two rows) is named, no other channel.
        let ev = late_thigh(None);
        assert_eq!(ev.coverage.len(), 2);
        assert!(ev.coverage_note().unwrap().contains("(thigh 2 of 4)"));
        // Channels with the same counts are named together, in channel order.
        let mut m = AngleMetrics::new("chain", EvalOptions::default());
        m.set_carried_channels([true; 7]);
        let mut e2 = Estimate::empty(0.0);
        e2.segment[1] = Some(0.1);
        e2.segment[2] = Some(0.2);
        m.push(&r, &Estimate::empty(0.0));
        m.push(&r, &e2);
        m.push(&r, &e);
        let note = m.evaluation().coverage_note().expect("a note");
        assert!(note.contains("(thigh 1 of 3, shank 2 of 3)"), "{note}");
        let mut m = AngleMetrics::new("chain", EvalOptions::default());
        m.push(&r, &Estimate::empty(0.0));
        m.push(&r, &e2);
        let note = m.evaluation().coverage_note().expect("a note");
        assert!(note.contains("(thigh, shank 1 of 2)"), "{note}");
        // Every carried channel scored wherever it has a reference: no note.
        let mut m = AngleMetrics::new("local", EvalOptions::default());
        m.push(&r, &e);
        assert_eq!(m.evaluation().coverage_note(), None);
    }
}
