//! The columns a report shows, read whole from the trial and estimate files.
//!
//! Everything is held in memory as `Option<f64>` columns (missing cells stay
//! `None`): a 10-minute 100 Hz walking trial with five estimates is a few
//! tens of MB. Only the diagnostic columns a panel draws
//! ([`crate::panels::wanted_diagnostic`]) are kept.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use limbfuse_core::sample::AngleChannel;
use limbfuse_core::GaitPhase;
use limbfuse_io::table::TableReader;
use limbfuse_io::{EstimateReader, FileError, TrialMeta, TrialReader};

/// One numeric column, a value (or a gap) per sample.
pub type Column = Vec<Option<f64>>;

/// The trial: time, reference angles and the extra columns the report uses.
#[derive(Debug, Clone)]
pub struct TrialData {
    /// The trial file.
    pub path: PathBuf,
    /// Its metadata (`# key: value` lines).
    pub meta: TrialMeta,
    /// Sample times (s).
    pub t: Vec<f64>,
    /// Reference angle per [`AngleChannel::ALL`] entry (rad), when the trial has it.
    pub reference: [Option<Column>; 7],
    /// Other numeric columns by name: gait references (`contact_*_ref`,
    /// `speed_ref`, the B-SLIP trials' CoM velocity `com_vx`), shank and foot sagittal gyros, stimulation `u_*`,
    /// activation `a_*`.
    pub columns: BTreeMap<String, Column>,
    /// `phase_ref` as 0 (SS1), 1 (DS), 2 (SS2), when present.
    pub phase_ref: Option<Column>,
    /// The unit checks `estimate` makes (a time column not in seconds,
    /// accelerometers in g, gyroscopes in deg/s; `limbfuse_eval::unit_warnings`).
    pub unit_warnings: Vec<String>,
    /// The trial's walking-speed reference is its CoM velocity
    /// (`limbfuse_eval::speed_from_com`: `com_vx` .. `com_vz`, no
    /// `speed_ref`, no `phase_ref`, as the independent simulator's walks);
    /// [`COM_SPEED`] then holds the horizontal CoM speed `evaluate` scores
    /// the gait-event and walking-speed estimates against.
    pub speed_from_com: bool,
}

/// The column of [`TrialData::columns`] holding the horizontal CoM speed
/// `hypot(com_vx, com_vz)` (m/s; y is up) on a trial whose speed reference
/// is its CoM velocity ([`TrialData::speed_from_com`]).
pub const COM_SPEED: &str = "com_speed_horizontal";

/// One estimate file.
#[derive(Debug, Clone)]
pub struct EstimateData {
    /// The estimate file.
    pub path: PathBuf,
    /// Label shown in legends: the file name.
    pub label: String,
    /// The `# method:` entry.
    pub method: String,
    /// Header entries (method, parameters, trial, command).
    pub meta: TrialMeta,
    /// Estimated angle per [`AngleChannel::ALL`] entry (rad), when the file has it.
    pub angle: [Option<Column>; 7],
    /// Estimated gait phase as 0 (SS1), 1 (DS), 2 (SS2), when the file has it.
    pub phase: Option<Column>,
    /// Estimated speed (m/s), when the file has it.
    pub speed: Option<Column>,
    /// Estimated foot contact (1 on the ground, 0 in swing), left then
    /// right, when the file has it.
    pub contact: [Option<Column>; 2],
    /// The kept diagnostic columns, by name without `diag_`.
    pub diag: BTreeMap<String, Column>,
}

/// The numeric trial columns kept besides the references (exact names).
const TRIAL_EXTRA: [&str; 7] = [
    "contact_left_ref",
    "contact_right_ref",
    "speed_ref",
    "com_vx",
    "com_vz",
    "shank_gyr_z",
    "foot_gyr_z",
];

/// Whether a trial column is kept in [`TrialData::columns`].
fn keep_trial_column(name: &str) -> bool {
    TRIAL_EXTRA.contains(&name) || name.starts_with("u_") || name.starts_with("a_")
}

/// `SS1`/`DS`/`SS2` as 0/1/2 (the order of paper 003's phase cycle).
pub fn phase_code(p: GaitPhase) -> f64 {
    match p {
        GaitPhase::Ss1 => 0.0,
        GaitPhase::Ds => 1.0,
        GaitPhase::Ss2 => 2.0,
    }
}

impl TrialData {
    /// Reads the whole trial.
    pub fn read(path: &Path) -> Result<Self, FileError> {
        let mut table = TableReader::open(path)?;
        let t_col = table.time_column()?;
        let ref_cols = AngleChannel::ALL.map(|c| table.column(&format!("{}_ref", c.name())));
        let extra: Vec<(String, usize)> = table
            .header()
            .iter()
            .enumerate()
            .filter(|(_, h)| keep_trial_column(h))
            .map(|(i, h)| (h.clone(), i))
            .collect();
        let phase_col = table.column("phase_ref");
        let meta = table.meta().clone();
        let mut t = Vec::new();
        let mut reference: [Option<Column>; 7] = ref_cols.map(|c| c.map(|_| Vec::new()));
        let mut columns: Vec<Column> = vec![Vec::new(); extra.len()];
        let mut phase_ref = phase_col.map(|_| Vec::new());
        let mut previous = None;
        while let Some(row) = table.next_row()? {
            let time = row.time(t_col, previous)?;
            previous = Some(time);
            t.push(time);
            for (col, out) in ref_cols.iter().zip(reference.iter_mut()) {
                if let (Some(c), Some(v)) = (col, out.as_mut()) {
                    v.push(row.number(*c)?);
                }
            }
            for ((_, c), out) in extra.iter().zip(columns.iter_mut()) {
                out.push(row.number(*c)?);
            }
            if let (Some(c), Some(v)) = (phase_col, phase_ref.as_mut()) {
                let text = row.text(c);
                let p = if text.is_empty() {
                    None
                } else {
                    let p = std::str::from_utf8(text)
                        .ok()
                        .and_then(GaitPhase::from_label)
                        .ok_or_else(|| row.cell_error(c, "a gait phase `SS1`, `DS` or `SS2`"))?;
                    Some(phase_code(p))
                };
                v.push(p);
            }
        }
        // (a second pass, over records: the checks read the IMU vectors)
        let mut reader = TrialReader::open(path)?;
        let speed_from_com = limbfuse_eval::speed_from_com(reader.layout());
        let unit_warnings = limbfuse_eval::summarise(&mut reader)?.warnings;
        let mut columns: BTreeMap<String, Column> =
            extra.into_iter().map(|(n, _)| n).zip(columns).collect();
        if speed_from_com {
            // (an audit 2026-12-05: `evaluate` scored `gait-events` and
            // `lowback-speed` on the independent walks against this speed,
            // the report said the trial had no reference to score them)
            let speed = match (columns.get("com_vx"), columns.get("com_vz")) {
                (Some(x), Some(z)) => x
                    .iter()
                    .zip(z)
                    .map(|(x, z)| Some(x.as_ref()?.hypot(*z.as_ref()?)))
                    .collect(),
                _ => vec![None; t.len()],
            };
            columns.insert(COM_SPEED.to_string(), speed);
        }
        Ok(TrialData {
            path: path.to_path_buf(),
            meta,
            t,
            reference,
            columns,
            phase_ref,
            unit_warnings,
            speed_from_com,
        })
    }

    /// The trial's file name.
    pub fn name(&self) -> String {
        file_name(&self.path)
    }

    /// The leg the single-leg column names refer to (`# leg:`, right when absent).
    pub fn leg(&self) -> &str {
        self.meta.get("leg").map_or("right", str::trim)
    }

    /// Median sample rate (Hz) from the time stamps, if there are two samples.
    pub fn sample_rate(&self) -> Option<f64> {
        let mut dt: Vec<f64> = self.t.windows(2).map(|w| w[1] - w[0]).collect();
        if dt.is_empty() {
            return None;
        }
        dt.sort_by(f64::total_cmp);
        Some(1.0 / dt[dt.len() / 2])
    }
}

impl EstimateData {
    /// Reads the whole estimate file, keeping the diagnostics `keep` accepts.
    pub fn read(path: &Path, keep: impl Fn(&str) -> bool) -> Result<Self, FileError> {
        let mut reader = EstimateReader::open(path)?;
        let method = reader.method().to_string();
        let meta = reader.meta().clone();
        let names: Vec<String> = reader.diagnostic_names().map(str::to_string).collect();
        let kept: Vec<(usize, String)> = names
            .into_iter()
            .enumerate()
            .filter(|(_, n)| keep(n))
            .collect();
        let mut angle: [Option<Column>; 7] =
            AngleChannel::ALL.map(|c| reader.has_angle(c).then(Vec::new));
        let mut phase = Vec::new();
        let mut speed = Vec::new();
        let mut contact: [Column; 2] = [Vec::new(), Vec::new()];
        let mut diag: Vec<Column> = vec![Vec::new(); kept.len()];
        while let Some((_, e)) = reader.next_estimate()? {
            for (c, out) in AngleChannel::ALL.iter().zip(angle.iter_mut()) {
                if let Some(v) = out.as_mut() {
                    v.push(e.angle(*c));
                }
            }
            phase.push(e.phase.map(phase_code));
            speed.push(e.speed);
            for (out, c) in contact.iter_mut().zip(e.contact) {
                out.push(c.map(|on| if on { 1.0 } else { 0.0 }));
            }
            for ((k, _), out) in kept.iter().zip(diag.iter_mut()) {
                out.push(e.diag[*k]);
            }
        }
        let any = |c: &Column| c.iter().any(Option::is_some);
        Ok(EstimateData {
            path: path.to_path_buf(),
            label: file_name(path),
            method,
            meta,
            angle,
            phase: any(&phase).then_some(phase),
            speed: any(&speed).then_some(speed),
            contact: contact.map(|c| any(&c).then_some(c)),
            diag: kept.into_iter().map(|(_, n)| n).zip(diag).collect(),
        })
    }
}

/// A path's file name (the whole path when it has none).
pub fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}
