//! Which evaluation a trial and an estimate get: angles, gait events and
//! walking speed (`limbfuse_eval::gait_events_evaluation`), or the gait
//! evaluation of paper 003 (`limbfuse_eval::gait_evaluation`). One rule for
//! `limbfuse evaluate` and Python's `limbfuse.evaluate`.

use limbfuse_io::{EstimateReader, TrialLayout};

/// What an estimate carries, as far as choosing its evaluation goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct EstimateContent {
    /// A foot-contact or a speed column.
    pub events_or_speed: bool,
    /// Any segment or joint angle.
    pub angles: bool,
}

impl EstimateContent {
    /// The content of an estimate file, from its header.
    pub fn of_file(r: &EstimateReader) -> Self {
        EstimateContent {
            events_or_speed: r.has_contact() || r.has_speed(),
            angles: r.has_any_angle(),
        }
    }
}

/// Whether a trial's walking-speed reference is its centre-of-mass velocity:
/// it has `com_vx` .. `com_vz` but no `speed_ref` and no `phase_ref` (a
/// paper-003 gait trial keeps its own evaluation). The independent
/// simulator's walks are such trials (their `com_*` is the hip joint
/// centre); `gait-events` and `lowback-speed` are then scored against the
/// horizontal CoM speed of each row ([`crate::gait_events_evaluation`]).
pub fn speed_from_com(layout: &TrialLayout) -> bool {
    layout.com_vel && !layout.speed_ref && !layout.phase_ref
}

/// The evaluation a trial and an estimate get.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EvaluationKind {
    /// Angle errors (the trial has angle references, or nothing else).
    Angles,
    /// Gait events, contacts and stride speed (docs/GAIT_EVENTS.md).
    GaitEvents,
    /// Phase, CoM and speed of a gait trial (paper 003).
    Gait,
}

/// Gait events when the trial has their references (`contact_*_ref`,
/// `speed_ref`) and either no angle reference or an estimate of events or
/// speed without angles (a real walk imported with angle *and* speed
/// references, scored for `gait-events` or `lowback-speed`); the paper-003
/// gait evaluation for a trial with `phase_ref` or a CoM and no angle
/// reference; angles otherwise.
pub fn evaluation_kind(layout: &TrialLayout, estimate: EstimateContent) -> EvaluationKind {
    let events_only = estimate.events_or_speed && !estimate.angles;
    let event_refs = layout.contact_ref.iter().any(|&b| b)
        || layout.speed_ref
        || (events_only && speed_from_com(layout));
    let angle_refs = layout.has_angle_reference();
    if event_refs && (!angle_refs || (estimate.events_or_speed && !estimate.angles)) {
        EvaluationKind::GaitEvents
    } else if !angle_refs && (layout.phase_ref || layout.com_pos) {
        EvaluationKind::Gait
    } else {
        EvaluationKind::Angles
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A speed or events estimate, and an angle estimate.
    const SPEED: EstimateContent = EstimateContent {
        events_or_speed: true,
        angles: false,
    };
    const ANGLES: EstimateContent = EstimateContent {
        events_or_speed: false,
        angles: true,
    };

    #[test]
    fn events_of_a_walk_with_angle_references_are_scored_as_events() {
        let mut l = TrialLayout::default();
        l.joint_ref[1] = true;
        l.speed_ref = true;
        let (speed, angles) = (SPEED, ANGLES);
        assert_eq!(evaluation_kind(&l, speed), EvaluationKind::GaitEvents);
        assert_eq!(evaluation_kind(&l, angles), EvaluationKind::Angles);
        l.joint_ref[1] = false;
        assert_eq!(evaluation_kind(&l, angles), EvaluationKind::GaitEvents);
        l.speed_ref = false;
        l.phase_ref = true;
        assert_eq!(evaluation_kind(&l, speed), EvaluationKind::Gait);
    }

    #[test]
    fn a_walk_with_a_com_velocity_scores_speed_estimates_against_it() {
        let mut l = TrialLayout::default();
        l.joint_ref[1] = true;
        l.com_pos = true;
        l.com_vel = true;
        let (speed, angles) = (SPEED, ANGLES);
        assert!(speed_from_com(&l));
        assert_eq!(evaluation_kind(&l, speed), EvaluationKind::GaitEvents);
        assert_eq!(evaluation_kind(&l, angles), EvaluationKind::Angles);
        // A paper-003 gait trial keeps its evaluation.
        l.joint_ref[1] = false;
        l.phase_ref = true;
        assert!(!speed_from_com(&l));
        assert_eq!(evaluation_kind(&l, speed), EvaluationKind::Gait);
    }
}
