//! The body every anthropometric default of limbfuse assumes when a trial
//! states none (no `# height_m:`, segment lengths, leg length or sensor
//! height): one height for every method, so that the chain's segment
//! lengths, `knee-kinematic`'s shank lever arm, the FES models' lower leg
//! and `lowback-speed`'s pendulum describe the same person.

/// Body height (m) of the anthropometric defaults: 1.75 m, the body
/// limbfuse's walking simulator is built for (`# height_m: 1.75`, its
/// segments, IMU mounts and normative curves; docs/SIMULATOR.md) and the
/// body the FES models' lower leg is scaled to (75 kg, 1.75 m: the thesis of
/// paper 004 reports no body size). Segment lengths and heights follow as
/// fractions of it from D. A. Winter, *Biomechanics and Motor Control of
/// Human Movement*, 4th ed., Wiley 2009, Table 4.1 / Fig. 4.1 (thigh
/// 0.245 H, shank 0.246 H, greater-trochanter height 0.530 H). Not fitted
/// to any recording. Until 2026-12-05 `lowback-speed` alone assumed a
/// 1.70 m body (pendulum 0.90 m).
pub const DEFAULT_BODY_HEIGHT_M: f64 = 1.75;

/// Body mass (kg) of the anthropometric defaults: 75 kg, with
/// [`DEFAULT_BODY_HEIGHT_M`] the subject the FES models' segment masses and
/// inertias are scaled to (Winter 2009 Table 4.1).
pub const DEFAULT_BODY_MASS_KG: f64 = 75.0;
