//! The `sdre` / `ekf` estimator over a plant (a model plus the mapping from
//! trial channels to its measurements and inputs), implementing
//! [`limbfuse_core::Estimator`].

use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{DiagnosticSet, Estimate, Estimator, EstimatorError, Sample, TimeStep};
use limbfuse_models::SdcModel;
use nalgebra::{SMatrix, SVector};

use super::continuous::{propagate, update_parts, ContinuousTuning, FilterState, Linearisation};
use super::gyro_spikes::GyroSpikeTest;

/// A model together with how a trial feeds it.
pub trait Plant<const N: usize, const M: usize, const U: usize> {
    /// The dynamic and measurement model.
    type Model: SdcModel<N, M, U>;
    /// The model.
    fn model(&self) -> &Self::Model;
    /// Model name as in trial metadata (`knee-fes`, `fixed-hip`).
    fn model_name(&self) -> &'static str;
    /// Names of the measurement rows, in order.
    fn measurement_names(&self) -> [&'static str; M];
    /// Names of the input channels, in order (trial column names).
    fn input_names(&self) -> [&'static str; U];
    /// The measurement rows present in `s`.
    fn measurement(&self, s: &Sample) -> [Option<f64>; M];
    /// The input channels present in `s`.
    fn input(&self, s: &Sample) -> [Option<f64>; U];
    /// Initial state from the first sample (static accelerometer inclination).
    fn initial_state(&self, s: &Sample) -> SVector<f64, N>;
    /// Initial covariance diagonal for a start at `s`: the tuning's `p0`
    /// unless the plant knows better from the sample.
    fn initial_covariance(&self, _s: &Sample, p0: &SVector<f64, N>) -> SVector<f64, N> {
        *p0
    }
    /// Which estimate channels [`Plant::fill`] sets.
    fn outputs(&self) -> Outputs;
    /// Writes the state into the estimate's angle channels.
    fn fill(&self, x: &SVector<f64, N>, e: &mut Estimate);
    /// Writes the plant's own parameters as `key: value` lines.
    fn describe(&self, out: &mut dyn fmt::Write) -> fmt::Result;
    /// The plant's declared diagnostics: the state's rate rows, `P_ii`,
    /// the restart count.
    type Diag: DiagnosticSet;
    /// Keys of the rate states `x[N/2..N]` (paper 004's `dq`), in state order.
    const RATE_DIAG: &'static [Self::Diag];
    /// Keys of the Riccati-solution diagonal `P_ii` (eq 4.16), in state order.
    const COVARIANCE_DIAG: &'static [Self::Diag];
    /// Key of the number of restarts after a non-finite state.
    const RESETS_DIAG: Self::Diag;
    /// Key of the number of samples whose input was missing and held
    /// ([`MAX_INPUT_HOLD_S`]); `None`: a plant without inputs.
    const HELD_INPUTS_DIAG: Option<Self::Diag> = None;

    /// Method name when the plant is not a paper-004 model (`None`: the
    /// filter reports `sdre` or `ekf` from its linearisation).
    fn method_name(&self) -> Option<&'static str> {
        None
    }

    /// Whether [`Plant::write_update_parts`] is called (it costs one more
    /// evaluation of the model per sample); off for the thesis plants.
    const UPDATE_PARTS: bool = false;

    /// Writes diagnostics of the parts of the state derivative at the
    /// sample time ([`super::continuous::update_parts`]: the model's
    /// prediction, the measurement correction, the diagonal of `K C`), `dt`
    /// the sample interval (`None` at the first sample). Called only when
    /// [`Plant::UPDATE_PARTS`].
    fn write_update_parts(
        &self,
        _parts: (&SVector<f64, N>, &SVector<f64, N>, &SVector<f64, N>),
        _dt: Option<f64>,
        _e: &mut Estimate,
    ) {
    }

    /// Writes the diagnostics of state `st` after `resets` restarts.
    /// Default: [`Plant::RATE_DIAG`] from `x[N/2..N]`, [`Plant::COVARIANCE_DIAG`]
    /// from `P_ii`, [`Plant::RESETS_DIAG`].
    fn write_diagnostics(&self, st: &FilterState<N>, resets: u32, e: &mut Estimate) {
        let mut d = e.diagnostics_mut::<Self::Diag>();
        for (key, i) in Self::RATE_DIAG.iter().zip(N / 2..N) {
            d.value(*key, st.x[i]);
        }
        for (i, key) in Self::COVARIANCE_DIAG.iter().enumerate() {
            d.value(*key, st.p[(i, i)]);
        }
        d.value(Self::RESETS_DIAG, f64::from(resets));
    }
}

/// The longest time (s) an input channel (the stimulation `u_ke`, the
/// fixed hip's motor torques) may be missing while the filter holds its
/// last value. Past it the model has no input: the filter gives no
/// estimate until the input is back, then restarts from that sample as at
/// the start and counts the restart in its `resets` diagnostic (ours,
/// 2026-12-06: until then a longer gap was an error that ended the whole
/// run).
/// Ours (issue 16): the thesis's stimulation pulses ramp from 0 to their
/// plateau in 1.5 s (docs/FES_ESTIMATION.md), so a value held for 0.1 s is
/// off by at most 0.1 / 1.5 = 7 % of the plateau, inside the 10 % torque
/// error the physics tuning admits
/// ([`super::knee_extended::extended_defaults::TORQUE_ERROR`]). The count
/// of held samples is the plant's `held_inputs` diagnostic.
pub const MAX_INPUT_HOLD_S: f64 = 0.1;

/// Whether a propagated state has diverged: a non-finite state or
/// covariance, or a covariance with a negative variance (no covariance has
/// one; the Riccati solution of eq 4.16 stays positive definite in exact
/// arithmetic). The negative variance is what RK4 leaves when the step cap
/// ([`super::propagation`]) cannot follow the Riccati equation: after
/// seconds without a gyro reading `P_22` grows to ~90 (rad/s)^2, and the
/// first interval with a reading again (Riccati rate `~2 P_22 / s_1` =
/// 2e7 /s, `s_1` = 1e-5) is ~200 times stiffer than the capped sub-steps
/// can follow; the state
/// then ends finite but ~1e9 rad off and stays there (issue 16:
/// `simulate knee-fes --no-noise`, whose still sensors the sample gate
/// rejects as stuck for the first 3 s).
fn diverged<const N: usize>(st: &FilterState<N>) -> bool {
    !(st.x.iter().all(|v| v.is_finite())
        && st.p.iter().all(|v| v.is_finite())
        && st.p.diagonal().iter().all(|v| *v >= 0.0))
}

/// The continuous-time estimator of paper 004 on plant `P`: `sdre` with
/// [`Linearisation::Sdc`], `ekf` with [`Linearisation::Jacobian`].
#[derive(Debug, Clone)]
pub struct FesFilter<P, const N: usize, const M: usize, const U: usize> {
    plant: P,
    lin: Linearisation,
    tuning: ContinuousTuning<N, M>,
    s_inv: SVector<f64, M>,
    time: TimeStep,
    state: Option<FilterState<N>>,
    y_prev: SVector<f64, M>,
    y_seen: [bool; M],
    u_prev: SVector<f64, U>,
    u_seen: [bool; U],
    /// Time of each input channel's last value.
    u_time: [f64; U],
    /// Samples with a held input.
    held: u32,
    resets: u32,
    /// The state was dropped for an input gap longer than
    /// [`MAX_INPUT_HOLD_S`]: the next start is a restart.
    input_gap: bool,
    /// Single-sample spikes of the gyroscope measurements (ours; kept over
    /// restarts: it tests the sensor, not the filter).
    spikes: [GyroSpikeTest; M],
    /// Whether `spikes` replaces readings.
    spike_test: bool,
    /// Which measurement channels are gyroscopes (`*_gyr*`), the ones
    /// `spikes` tests.
    gyro_channel: [bool; M],
}

impl<P, const N: usize, const M: usize, const U: usize> FesFilter<P, N, M, U>
where
    P: Plant<N, M, U>,
{
    /// A filter on `plant`. `S` entries must be positive (they are inverted).
    pub fn new(plant: P, lin: Linearisation, tuning: ContinuousTuning<N, M>) -> Self {
        let s_inv = tuning.s.map(|s| if s > 0.0 { 1.0 / s } else { 0.0 });
        let gyro_channel = plant.measurement_names().map(|n| n.contains("_gyr"));
        FesFilter {
            plant,
            lin,
            tuning,
            s_inv,
            time: TimeStep::new(),
            state: None,
            y_prev: SVector::zeros(),
            y_seen: [false; M],
            u_prev: SVector::zeros(),
            u_seen: [false; U],
            u_time: [0.0; U],
            held: 0,
            resets: 0,
            input_gap: false,
            spikes: [GyroSpikeTest::default(); M],
            spike_test: true,
            gyro_channel,
        }
    }

    /// With `false`, every gyroscope reading the sample gate passes is a
    /// measurement, as in paper 004; with `true` (the default) a
    /// single-sample spike is replaced by the median of the last three
    /// readings (`fes::gyro_spikes`; docs/ROBUST_INPUT.md, "Gyroscope
    /// spikes in the FES filters").
    pub fn with_gyro_spike_test(self, on: bool) -> Self {
        FesFilter {
            spike_test: on,
            ..self
        }
    }

    /// The plant.
    pub fn plant(&self) -> &P {
        &self.plant
    }

    /// The tuning in use.
    pub fn tuning(&self) -> &ContinuousTuning<N, M> {
        &self.tuning
    }

    /// Current state and Riccati solution, once started.
    pub fn state(&self) -> Option<&FilterState<N>> {
        self.state.as_ref()
    }

    /// The inputs at `s`; `None` while one is unknown: not yet seen, or
    /// missing for longer than [`MAX_INPUT_HOLD_S`].
    fn inputs(&mut self, s: &Sample) -> Result<Option<SVector<f64, U>>, EstimatorError> {
        let names = self.plant.input_names();
        let mut u = self.u_prev;
        let mut held = false;
        let mut known = true;
        for (i, v) in self.plant.input(s).into_iter().enumerate() {
            match v {
                Some(v) if v.is_finite() => {
                    u[i] = v;
                    self.u_seen[i] = true;
                    self.u_time[i] = s.t;
                }
                Some(_) => return Err(EstimatorError::NonFinite { channel: names[i] }),
                None if !self.u_seen[i] => known = false,
                // Dropout: hold the last input, for at most MAX_INPUT_HOLD_S.
                None if s.t - self.u_time[i] > MAX_INPUT_HOLD_S * (1.0 + 1e-9) => known = false,
                None => held = true,
            }
        }
        if !known {
            return Ok(None);
        }
        if held {
            self.held += 1;
        }
        Ok(Some(u))
    }

    /// The estimate of a sample without its inputs: no angles, the
    /// counts. The state is dropped, so the filter restarts when the
    /// inputs are back.
    fn without_inputs(&mut self, s: &Sample) -> Estimate {
        if self.state.take().is_some() {
            self.input_gap = true;
        }
        let mut e = Estimate::empty(s.t);
        let mut d = e.diagnostics_mut::<P::Diag>();
        d.value(P::RESETS_DIAG, f64::from(self.resets));
        if let Some(key) = P::HELD_INPUTS_DIAG {
            d.value(key, f64::from(self.held));
        }
        e
    }

    fn restart(&mut self, s: &Sample) {
        let x = self.plant.initial_state(s);
        let p0 = self.plant.initial_covariance(s, &self.tuning.p0);
        self.state = Some(FilterState {
            x,
            p: SMatrix::from_diagonal(&p0),
        });
    }
}

impl<P, const N: usize, const M: usize, const U: usize> Estimator for FesFilter<P, N, M, U>
where
    P: Plant<N, M, U>,
{
    fn name(&self) -> &'static str {
        if let Some(name) = self.plant.method_name() {
            return name;
        }
        match self.lin {
            Linearisation::Sdc => "sdre",
            Linearisation::Jacobian => "ekf",
        }
    }

    fn outputs(&self) -> Outputs {
        self.plant.outputs()
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(out, "model: {}", self.plant.model_name())?;
        writeln!(
            out,
            "linearisation: {}",
            match self.lin {
                Linearisation::Sdc =>
                    "state-dependent coefficients (paper 004 eqs 4.11-4.13, 4.25)",
                Linearisation::Jacobian => "Jacobians df/dx, dh/dx",
            }
        )?;
        write_names(out, "measurements", &self.plant.measurement_names())?;
        write_names(out, "inputs", &self.plant.input_names())?;
        write_list(out, "q", self.tuning.q.as_slice())?;
        write_list(out, "s", self.tuning.s.as_slice())?;
        writeln!(out, "a: {}", self.tuning.a)?;
        write_list(out, "p0", self.tuning.p0.as_slice())?;
        writeln!(out, "max_substep_s: {}", self.tuning.max_substep)?;
        writeln!(
            out,
            "propagation: RK4 on state and Riccati equation, first-order hold of y and u"
        )?;
        self.plant.describe(out)
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        <P::Diag as DiagnosticSet>::NAMES
    }

    fn rejected_readings(&self) -> [u64; 3] {
        [self.spikes.iter().map(GyroSpikeTest::refused).sum(), 0, 0]
    }

    fn reset(&mut self) {
        self.time.reset();
        self.state = None;
        self.spikes = [GyroSpikeTest::default(); M];
        self.y_seen = [false; M];
        self.u_seen = [false; U];
        self.held = 0;
        self.resets = 0;
        self.input_gap = false;
    }

    fn step(&mut self, s: &Sample) -> Result<Estimate, EstimatorError> {
        let dt = self.time.advance(s.t)?;
        let Some(u) = self.inputs(s)? else {
            return Ok(self.without_inputs(s));
        };
        let mut meas = self.plant.measurement(s);
        if self.spike_test {
            for (i, (m, test)) in meas.iter_mut().zip(&mut self.spikes).enumerate() {
                if let Some(v) = m.filter(|v| v.is_finite() && self.gyro_channel[i]) {
                    if let Some(r) = test.replacement(s.t, v, self.tuning.s[i]) {
                        *m = Some(r);
                    }
                }
            }
        }
        let mut y = self.y_prev;
        let mut weight = self.s_inv;
        for (i, m) in meas.iter().enumerate() {
            match m {
                Some(v) if v.is_finite() => y[i] = *v,
                Some(_) => {
                    return Err(EstimatorError::NonFinite {
                        channel: self.plant.measurement_names()[i],
                    })
                }
                None => weight[i] = 0.0,
            }
            if !self.y_seen[i] {
                weight[i] = 0.0;
            }
        }
        match (dt, self.state.as_mut()) {
            (Some(dt), Some(st)) => {
                propagate(
                    self.plant.model(),
                    self.lin,
                    st,
                    dt,
                    (&self.y_prev, &y),
                    (&self.u_prev, &u),
                    &weight,
                    &self.tuning,
                );
                if diverged(st) {
                    self.resets += 1;
                    self.restart(s);
                }
            }
            _ => {
                if core::mem::take(&mut self.input_gap) {
                    self.resets += 1;
                }
                self.restart(s)
            }
        }
        for (i, m) in meas.iter().enumerate() {
            if m.is_some() {
                self.y_seen[i] = true;
            }
        }
        self.y_prev = y;
        self.u_prev = u;
        let st = self
            .state
            .as_ref()
            .ok_or(EstimatorError::Numerical("no state"))?;
        let mut e = Estimate::empty(s.t);
        self.plant.fill(&st.x, &mut e);
        if !self.y_seen.iter().any(|seen| *seen) {
            // No measurement yet: the state is the prior, not an estimate
            // (an audit: `knee-kinematic` on a trial whose IMU cells were all
            // empty wrote a constant 90 deg knee).
            e.segment = [None; 4];
            e.joint = [None; 3];
        }
        self.plant.write_diagnostics(st, self.resets, &mut e);
        if let Some(key) = P::HELD_INPUTS_DIAG {
            e.diagnostics_mut::<P::Diag>()
                .value(key, f64::from(self.held));
        }
        if P::UPDATE_PARTS {
            let mut w = weight;
            for (i, seen) in self.y_seen.iter().enumerate() {
                if !seen {
                    w[i] = 0.0;
                }
            }
            let (pred, corr, pull) = update_parts(self.plant.model(), self.lin, st, &y, &u, &w);
            self.plant
                .write_update_parts((&pred, &corr, &pull), dt, &mut e);
        }
        Ok(e)
    }
}

/// Writes `key: v1, v2, ...`.
fn write_list(out: &mut dyn fmt::Write, key: &str, v: &[f64]) -> fmt::Result {
    write!(out, "{key}: ")?;
    for (i, x) in v.iter().enumerate() {
        if i > 0 {
            write!(out, ", ")?;
        }
        write!(out, "{x}")?;
    }
    writeln!(out)
}

/// Writes `key: a, b, ...`.
fn write_names(out: &mut dyn fmt::Write, key: &str, v: &[&str]) -> fmt::Result {
    write!(out, "{key}: ")?;
    for (i, x) in v.iter().enumerate() {
        if i > 0 {
            write!(out, ", ")?;
        }
        write!(out, "{x}")?;
    }
    writeln!(out)
}
