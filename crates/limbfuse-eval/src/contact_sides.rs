//! The sides of contacts a method pools (`lowback-speed`: `diag_ic` for
//! every contact, `diag_ic_right` / `diag_ic_left` for those whose foot it
//! told, 2 s later; docs/GAIT_EVENTS.md, `lowback-speed` item 7), against the foot of the
//! reference contact each is paired with: the timing stays pooled (a
//! contact without a side is still a contact), and the sides are scored
//! apart, as mobgap scores its laterality apart from its contacts.

use limbfuse_core::Side;
use serde_json::{json, Value};

use crate::gait_event_columns::Columns;
use crate::gait_events_evaluation::steps;

/// Two times are one contact's: both columns hold the same value.
const SAME_CONTACT_S: f64 = 1e-9;

/// How the sides of the paired contacts compare with the reference's feet.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ContactSides {
    /// Estimated contacts paired with a reference contact.
    pub n_paired: usize,
    /// Of those, contacts given a side.
    pub n_sided: usize,
    /// Of those, contacts given the reference contact's foot.
    pub n_correct: usize,
}

impl ContactSides {
    /// Scores the pooled `pairs` (reference index, estimated index) of
    /// `reference` and `estimated`; `None` when the estimate has no side
    /// columns at all (a method that does not tell the foot).
    pub(crate) fn score(
        c: &Columns,
        reference: &[f64],
        estimated: &[f64],
        pairs: &[(usize, usize)],
    ) -> Option<ContactSides> {
        if !c.has_ic_sides {
            return None;
        }
        let right_ref = steps(&c.t, &c.reference[Side::Right.index()], true);
        let is_in = |list: &[f64], x: f64| list.iter().any(|&y| (y - x).abs() <= SAME_CONTACT_S);
        let mut out = ContactSides::default();
        for &(i, j) in pairs {
            out.n_paired += 1;
            let reference_right = is_in(&right_ref, reference[i]);
            let told = if is_in(&c.ic[Side::Right.index()], estimated[j]) {
                Some(true)
            } else if is_in(&c.ic[Side::Left.index()], estimated[j]) {
                Some(false)
            } else {
                None
            };
            if let Some(right) = told {
                out.n_sided += 1;
                out.n_correct += usize::from(right == reference_right);
            }
        }
        Some(out)
    }

    /// % of the sided contacts with the reference's foot.
    pub fn accuracy_pct(&self) -> Option<f64> {
        (self.n_sided > 0).then(|| 100.0 * self.n_correct as f64 / self.n_sided as f64)
    }

    /// The JSON object (`contact_sides` in `evaluate --json`).
    pub fn to_json(&self) -> Value {
        json!({
            "n_paired": self.n_paired,
            "n_sided": self.n_sided,
            "n_correct": self.n_correct,
            "accuracy_pct": self.accuracy_pct(),
        })
    }

    /// The text lines.
    pub fn to_text(&self) -> String {
        let pct = self
            .accuracy_pct()
            .map_or("-".to_string(), |p| format!("{p:.1} %"));
        format!(
            "(initial contacts pooled over both feet for their timing)\n\
             contact side     {} of {} sided contacts on the reference's foot ({pct}); {} of {} paired contacts without a side\n",
            self.n_correct,
            self.n_sided,
            self.n_paired - self.n_sided,
            self.n_paired,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn columns() -> Columns {
        // Rows every 0.1 s; right contact at 0.2 s, left at 0.7 s.
        let t: Vec<f64> = (0..10).map(|k| k as f64 * 0.1).collect();
        let mut c = Columns {
            t,
            has_ic_sides: true,
            ..Default::default()
        };
        let (r, l) = (Side::Right.index(), Side::Left.index());
        c.reference[r] = (0..10).map(|k| Some((2..6).contains(&k))).collect();
        c.reference[l] = (0..10).map(|k| Some(!(1..7).contains(&k))).collect();
        c
    }

    #[test]
    fn sides_are_counted_against_the_paired_reference_foot() {
        let mut c = columns();
        let (r, l) = (Side::Right.index(), Side::Left.index());
        let reference = [0.2, 0.7000000000000001];
        let estimated = [0.23, 0.74];
        // The first told right (correct), the second told right (wrong).
        c.ic[r] = vec![0.23, 0.74];
        let s = ContactSides::score(&c, &reference, &estimated, &[(0, 0), (1, 1)]).unwrap();
        assert_eq!((s.n_paired, s.n_sided, s.n_correct), (2, 2, 1));
        assert_eq!(s.accuracy_pct(), Some(50.0));
        // The second told left: both correct; the first without a side.
        c.ic[r].clear();
        c.ic[l] = vec![0.74];
        let s = ContactSides::score(&c, &reference, &estimated, &[(0, 0), (1, 1)]).unwrap();
        assert_eq!((s.n_paired, s.n_sided, s.n_correct), (2, 1, 1));
        assert!(s.to_text().contains("1 of 1 sided contacts on the reference's foot (100.0 %); 1 of 2 paired contacts without a side"));
    }

    #[test]
    fn no_side_columns_no_score() {
        let mut c = columns();
        c.has_ic_sides = false;
        assert_eq!(ContactSides::score(&c, &[0.2], &[0.2], &[(0, 0)]), None);
    }
}
