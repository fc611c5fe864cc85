//! Trial columns held as numpy arrays (SPEC section 2 names) <-> the
//! [`Record`]s the estimators read.
//!
//! A trial holds the columns `limbfuse_io::TrialReader` reads: the IMUs,
//! encoders, model inputs and CoM measurements of the leg, the other leg's
//! IMUs (`S_<other>_acc_A`, `S_<other>_gyr_A`, the other side of the
//! trial's `# leg:`, right when absent: [`leg_of`], named by
//! `limbfuse_io::layout`), and the references (`S_ref`, `J_ref`, `com_*`,
//! `phase_ref`, `contact_left_ref` / `contact_right_ref`: 1, 0 or missing,
//! `speed_ref`).
//!
//! Inside the extension a missing cell is NaN: the Python layer refuses NaN
//! in the arrays a user gives (missing samples are masked) and fills the
//! masked cells with NaN before calling in. As in `TrialReader`, an IMU
//! vector with a missing axis cell keeps its other axes
//! (`ImuSample::set_acc_axes`, issue 18 item 2), while a quaternion or a
//! CoM reference vector is present only when all its components are
//! ([`crate::column_records`]).

use limbfuse_core::sample::{ComMeasurement, GaitPhase, ModelInputs};
use limbfuse_core::{Joint, Record, Segment, ShownNumber, Side};
use limbfuse_io::layout::{contact_ref_column, other_leg_prefix, AXES, QUAT, SPEED_REF};
use limbfuse_io::{TrialLayout, TrialMeta};

use crate::column_records::RecordPlan;
use crate::column_samples::SampleColumns;

/// One numeric trial column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channel {
    /// `S_acc_A`: segment index, axis index.
    Acc(usize, usize),
    /// `S_gyr_A`.
    Gyr(usize, usize),
    /// `S_quat_C` (w, x, y, z).
    Quat(usize, usize),
    /// `J_enc`.
    Encoder(usize),
    /// `u_ke`, `u_kf`, `u_he`, `u_hf`.
    Stim(usize),
    /// `tau_J_motor`.
    Motor(usize),
    /// `com_meas_x` .. `com_meas_vz`.
    ComMeas(usize),
    /// `S_ref`.
    SegmentRef(usize),
    /// `J_ref`.
    JointRef(usize),
    /// `com_x`, `com_y`, `com_z`.
    ComPos(usize),
    /// `com_vx`, `com_vy`, `com_vz`.
    ComVel(usize),
    /// `S_<side>_acc_A` of the other leg (`side`): segment index, axis index.
    OtherAcc(Side, usize, usize),
    /// `S_<side>_gyr_A` of the other leg.
    OtherGyr(Side, usize, usize),
    /// `contact_left_ref`, `contact_right_ref` (1 on the ground, 0 swing).
    ContactRef(Side),
    /// `speed_ref` (m/s).
    SpeedRef,
}

/// The column of the gait-phase reference (text cells `SS1`, `DS`, `SS2`).
pub const PHASE_REF: &str = "phase_ref";

const COM_POS: [&str; 3] = ["com_x", "com_y", "com_z"];
const COM_VEL: [&str; 3] = ["com_vx", "com_vy", "com_vz"];

/// The side of a trial's single-leg columns: [`TrialMeta::leg`], the rule
/// `TrialReader` reads it by (SPEC section 2: right when absent).
pub fn leg_of(meta: &TrialMeta) -> Result<Side, String> {
    meta.leg()
}

impl Channel {
    /// Every numeric channel of a trial whose other leg is `other`, in the
    /// writers' column order.
    pub fn all(other: Side) -> Vec<Channel> {
        let mut c = Vec::with_capacity(112);
        for s in 0..4 {
            c.extend((0..3).map(|k| Channel::Acc(s, k)));
            c.extend((0..3).map(|k| Channel::Gyr(s, k)));
            c.extend((0..4).map(|k| Channel::Quat(s, k)));
        }
        for s in 0..4 {
            c.extend((0..3).map(|k| Channel::OtherAcc(other, s, k)));
            c.extend((0..3).map(|k| Channel::OtherGyr(other, s, k)));
        }
        c.extend((0..3).map(Channel::Encoder));
        c.extend((0..4).map(Channel::Stim));
        c.extend((0..3).map(Channel::Motor));
        c.extend((0..6).map(Channel::ComMeas));
        c.extend((0..4).map(Channel::SegmentRef));
        c.extend((0..3).map(Channel::JointRef));
        c.extend((0..3).map(Channel::ComPos));
        c.extend((0..3).map(Channel::ComVel));
        c.extend(Side::BOTH.map(Channel::ContactRef));
        c.push(Channel::SpeedRef);
        c
    }

    /// The column name.
    pub fn name(self) -> String {
        let seg = |s: usize| Segment::ALL[s].name();
        let joint = |j: usize| Joint::ALL[j].name();
        match self {
            Channel::Acc(s, k) => format!("{}_acc_{}", seg(s), AXES[k]),
            Channel::Gyr(s, k) => format!("{}_gyr_{}", seg(s), AXES[k]),
            Channel::Quat(s, k) => format!("{}_quat_{}", seg(s), QUAT[k]),
            Channel::Encoder(j) => format!("{}_enc", joint(j)),
            Channel::Stim(k) => ModelInputs::STIM_NAMES[k].to_string(),
            Channel::Motor(j) => format!("tau_{}_motor", joint(j)),
            Channel::ComMeas(k) => ComMeasurement::NAMES[k].to_string(),
            Channel::SegmentRef(s) => format!("{}_ref", seg(s)),
            Channel::JointRef(j) => format!("{}_ref", joint(j)),
            Channel::ComPos(k) => COM_POS[k].to_string(),
            Channel::ComVel(k) => COM_VEL[k].to_string(),
            Channel::OtherAcc(side, s, k) => {
                format!("{}acc_{}", other_leg_prefix(Segment::ALL[s], side), AXES[k])
            }
            Channel::OtherGyr(side, s, k) => {
                format!("{}gyr_{}", other_leg_prefix(Segment::ALL[s], side), AXES[k])
            }
            Channel::ContactRef(side) => contact_ref_column(side),
            Channel::SpeedRef => SPEED_REF.to_string(),
        }
    }

    /// The channel named `name`, if it is a column of a trial whose other
    /// leg is `other`.
    pub fn parse(name: &str, other: Side) -> Option<Channel> {
        Channel::all(other).into_iter().find(|c| c.name() == name)
    }

    /// The value in `r` (`None` when missing).
    pub fn get(self, r: &Record) -> Option<f64> {
        let (s, re) = (&r.sample, &r.reference);
        match self {
            Channel::Acc(i, k) => s.imu[i].acc_axis(k),
            Channel::Gyr(i, k) => s.imu[i].gyr_axis(k),
            Channel::Quat(i, k) => s.imu[i].quat.map(|q| q[k]),
            Channel::Encoder(j) => s.encoder[j],
            Channel::Stim(k) => s.inputs.stim[k],
            Channel::Motor(j) => s.inputs.motor_torque[j],
            Channel::ComMeas(k) => s.com.values()[k],
            Channel::SegmentRef(i) => re.segment[i],
            Channel::JointRef(j) => re.joint[j],
            Channel::ComPos(k) => re.com_pos.map(|v| v[k]),
            Channel::ComVel(k) => re.com_vel.map(|v| v[k]),
            Channel::OtherAcc(_, i, k) => s.other_leg_imu[i].acc_axis(k),
            Channel::OtherGyr(_, i, k) => s.other_leg_imu[i].gyr_axis(k),
            Channel::ContactRef(side) => re.contact[side.index()].map(f64::from),
            Channel::SpeedRef => re.speed,
        }
    }

    /// Marks the channel present in `layout`.
    fn mark(self, l: &mut TrialLayout) {
        match self {
            Channel::Acc(i, _) => l.acc[i] = true,
            Channel::Gyr(i, _) => l.gyr[i] = true,
            Channel::Quat(i, _) => l.quat[i] = true,
            Channel::Encoder(j) => l.encoder[j] = true,
            Channel::Stim(k) => l.stim[k] = true,
            Channel::Motor(j) => l.motor_torque[j] = true,
            Channel::ComMeas(k) => l.com_meas[k] = true,
            Channel::SegmentRef(i) => l.segment_ref[i] = true,
            Channel::JointRef(j) => l.joint_ref[j] = true,
            Channel::ComPos(_) => l.com_pos = true,
            Channel::ComVel(_) => l.com_vel = true,
            Channel::OtherAcc(_, i, _) => l.other_acc[i] = true,
            Channel::OtherGyr(_, i, _) => l.other_gyr[i] = true,
            Channel::ContactRef(side) => l.contact_ref[side.index()] = true,
            Channel::SpeedRef => l.speed_ref = true,
        }
    }

    /// Checks the cells of a channel with a fixed set of values (a foot
    /// contact: 1, 0 or missing, as `TrialReader` reads it).
    fn check_cells(self, values: &[f64]) -> Result<(), String> {
        if !matches!(self, Channel::ContactRef(_)) {
            return Ok(());
        }
        match values
            .iter()
            .position(|&v| !(v.is_nan() || v == 0.0 || v == 1.0))
        {
            None => Ok(()),
            Some(i) => Err(format!(
                "channel `{}`, sample {i}: expected a foot contact 1 (on the ground), 0 (swing) or a missing sample, found {}",
                self.name(),
                values[i]
            )),
        }
    }
}

/// A trial held as columns borrowed from numpy arrays.
#[derive(Debug)]
pub struct TrialColumns<'a> {
    /// Time (s), strictly increasing.
    pub t: &'a [f64],
    columns: Vec<(Channel, &'a [f64])>,
    phase: Option<Vec<Option<GaitPhase>>>,
    layout: TrialLayout,
}

impl<'a> TrialColumns<'a> {
    /// Checks the column names and lengths, the time column and the
    /// contact cells, for a trial whose single-leg columns are of `leg`
    /// ([`leg_of`]). `phase` holds the `phase_ref` cells (`None` or `""` =
    /// missing).
    pub fn new(
        t: &'a [f64],
        named: Vec<(String, &'a [f64])>,
        phase: Option<Vec<Option<String>>>,
        leg: Side,
    ) -> Result<Self, String> {
        check_time(t)?;
        let mut layout = TrialLayout {
            leg,
            ..TrialLayout::default()
        };
        let other = layout.other_leg();
        let mut columns: Vec<(Channel, &[f64])> = Vec::with_capacity(named.len());
        for (name, values) in named {
            let c = Channel::parse(&name, other).ok_or_else(|| unknown_column(&name, other))?;
            if columns.iter().any(|(k, _)| *k == c) {
                return Err(format!("channel `{name}` is given twice"));
            }
            if values.len() != t.len() {
                return Err(format!(
                    "channel `{name}` has {} samples but `t` has {} (every channel needs one value per time)",
                    values.len(),
                    t.len()
                ));
            }
            c.check_cells(values)?;
            c.mark(&mut layout);
            columns.push((c, values));
        }
        // A vector group needs all its components, as in a trial file.
        let names: Vec<Channel> = columns.iter().map(|(c, _)| *c).collect();
        for c in Channel::all(other) {
            let group_has = |f: &dyn Fn(Channel) -> bool| names.iter().any(|k| f(*k));
            let missing_of_group = match c {
                Channel::Acc(i, _) => group_has(&|k| matches!(k, Channel::Acc(j, _) if j == i)),
                Channel::Gyr(i, _) => group_has(&|k| matches!(k, Channel::Gyr(j, _) if j == i)),
                Channel::Quat(i, _) => group_has(&|k| matches!(k, Channel::Quat(j, _) if j == i)),
                Channel::OtherAcc(_, i, _) => {
                    group_has(&|k| matches!(k, Channel::OtherAcc(_, j, _) if j == i))
                }
                Channel::OtherGyr(_, i, _) => {
                    group_has(&|k| matches!(k, Channel::OtherGyr(_, j, _) if j == i))
                }
                Channel::ComPos(_) => group_has(&|k| matches!(k, Channel::ComPos(_))),
                Channel::ComVel(_) => group_has(&|k| matches!(k, Channel::ComVel(_))),
                _ => false,
            };
            if missing_of_group && !names.contains(&c) {
                return Err(format!(
                    "incomplete channel group: channel `{}` is missing (a 3-axis vector or quaternion needs all its components)",
                    c.name()
                ));
            }
        }
        let phase = match phase {
            None => None,
            Some(cells) => {
                layout.phase_ref = true;
                Some(phase_cells(PHASE_REF, &cells, t.len())?)
            }
        };
        Ok(TrialColumns {
            t,
            columns,
            phase,
            layout,
        })
    }

    /// The channels present.
    pub fn layout(&self) -> &TrialLayout {
        &self.layout
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Where each record field comes from (resolved once for a run).
    pub fn plan(&self) -> RecordPlan<'_> {
        RecordPlan::new(self.t, &self.columns, self.phase.as_deref())
    }

    /// The input columns, each with the sample field it fills (resolved
    /// once for a run).
    pub fn inputs(&self) -> SampleColumns<'_> {
        SampleColumns::new(self.t, &self.columns)
    }

    /// Every record, in order.
    pub fn records(&self) -> impl Iterator<Item = Record> + '_ {
        let plan = self.plan();
        (0..self.len()).map(move |i| {
            let mut r = Record::default();
            plan.fill(i, &mut r);
            r
        })
    }
}

/// Gait-phase cells (`SS1`, `DS`, `SS2`; `None` or `""` = missing) of the
/// column `name`, which must have `n` of them.
pub fn phase_cells(
    name: &str,
    cells: &[Option<String>],
    n: usize,
) -> Result<Vec<Option<GaitPhase>>, String> {
    if cells.len() != n {
        return Err(format!(
            "channel `{name}` has {} samples but `t` has {n}",
            cells.len()
        ));
    }
    let mut out = Vec::with_capacity(n);
    for (i, c) in cells.iter().enumerate() {
        out.push(match c.as_deref() {
            None | Some("") => None,
            Some(text) => Some(GaitPhase::from_label(text).ok_or_else(|| {
                format!("channel `{name}`, sample {i}: expected a gait phase `SS1`, `DS` or `SS2` (or an empty cell), found `{text}`")
            })?),
        });
    }
    Ok(out)
}

/// The first of `names` that is no trial channel of a trial whose
/// single-leg columns are of `leg`, as [`TrialColumns::new`] names it
/// (checked before the arrays are converted, so that a misspelt name is
/// what a user is told, not the NaN in its array).
pub fn check_names<'n>(names: impl IntoIterator<Item = &'n str>, leg: Side) -> Result<(), String> {
    let other = TrialLayout {
        leg,
        ..TrialLayout::default()
    }
    .other_leg();
    for name in names {
        Channel::parse(name, other).ok_or_else(|| unknown_column(name, other))?;
    }
    Ok(())
}

fn unknown_column(name: &str, other: Side) -> String {
    if name == "t" {
        return "`t` is the time array, not a channel".into();
    }
    let other_foot = other_leg_prefix(Segment::Foot, other);
    format!(
        "unknown channel `{name}`: trial channels are named as in SPEC section 2 (e.g. `thigh_gyr_x`, `knee_enc`, `thigh_ref`, `u_ke`, `com_meas_x`, `contact_left_ref`, `speed_ref`; the other leg's IMUs `{other_foot}gyr_x`, ... in a trial of the {} leg: `leg` metadata, right when absent)",
        other.other().name()
    )
}

/// `t` must be non-empty, finite and strictly increasing.
pub fn check_time(t: &[f64]) -> Result<(), String> {
    if t.is_empty() {
        return Err("no samples: `t` is empty".into());
    }
    for (i, w) in t.iter().enumerate() {
        if !w.is_finite() {
            return Err(format!(
                "`t`, sample {i}: time must be a finite number, found {}",
                ShownNumber(*w)
            ));
        }
        if i > 0 && *w <= t[i - 1] {
            return Err(format!(
                "`t`, sample {i}: time must increase strictly, but {} follows {}",
                ShownNumber(*w),
                ShownNumber(t[i - 1])
            ));
        }
    }
    Ok(())
}

/// A trial as owned columns (NaN = missing), in the writers' column order.
#[derive(Debug, Default)]
pub struct OwnedColumns {
    /// Time (s).
    pub t: Vec<f64>,
    /// Channel names and values.
    pub columns: Vec<(String, Vec<f64>)>,
    /// `phase_ref` cells, when the trial has them.
    pub phase: Option<Vec<Option<&'static str>>>,
}

impl OwnedColumns {
    /// Empty columns for `layout`, with room for `n` samples.
    pub fn new(layout: &TrialLayout, n: usize) -> (Self, Vec<Channel>) {
        let other = layout.other_leg();
        let channels: Vec<Channel> = layout
            .column_names()
            .iter()
            .filter_map(|n| Channel::parse(n, other))
            .collect();
        let cols = OwnedColumns {
            t: Vec::with_capacity(n),
            columns: channels
                .iter()
                .map(|c| (c.name(), Vec::with_capacity(n)))
                .collect(),
            phase: layout.phase_ref.then(|| Vec::with_capacity(n)),
        };
        (cols, channels)
    }

    /// Appends one record.
    pub fn push(&mut self, channels: &[Channel], r: &Record) {
        self.t.push(r.sample.t);
        for (c, (_, v)) in channels.iter().zip(self.columns.iter_mut()) {
            v.push(c.get(r).unwrap_or(f64::NAN));
        }
        if let Some(p) = &mut self.phase {
            p.push(r.reference.phase.map(GaitPhase::label));
        }
    }

    /// The columns of `records` with `layout`.
    pub fn of_records<'r>(
        layout: &TrialLayout,
        records: impl IntoIterator<Item = &'r Record>,
    ) -> Self {
        let (mut cols, channels) = Self::new(layout, 0);
        for r in records {
            cols.push(&channels, r);
        }
        cols
    }
}
