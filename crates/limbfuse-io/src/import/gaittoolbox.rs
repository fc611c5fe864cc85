//! The gaittoolbox walking trial: `imu-<segment>.csv` (Xsens MTx) and a
//! Vicon file of joint centres (`vicon-right.csv`, `vicon-left.csv` or the
//! toolbox's `vicon.csv`) in one folder, 100 Hz, sample k of every file being
//! the same instant; either leg (`gaittoolbox_leg`). See `docs/IMPORTERS.md`.

use std::path::{Path, PathBuf};

use limbfuse_core::{ImuSample, Joint, Record, Segment, Side};
use nalgebra::Vector3;

use super::gaittoolbox_leg::leg_files;
use super::sagittal_reference::{sagittal_reference, JointCentres, SagittalParams};
use super::{fmt, read_lines, Header, ImportError, ImportedTrial};
use crate::layout::TrialLayout;
use crate::meta::TrialMeta;

/// Options of [`import_gaittoolbox_with`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GaittoolboxOptions {
    /// Advance the IMU streams by this many samples (record k gets IMU sample
    /// k + shift; IMU channels are `None` where that is outside the file).
    /// Default 0: no shift. The lag measured on the shared trial is about 2
    /// samples (`docs/IMPORTERS.md`).
    pub shift_imu_samples: i32,
    /// How the reference angles are derived.
    pub reference: SagittalParams,
    /// The leg to import; `None`: the one the folder holds (the right
    /// when it holds both).
    pub leg: Option<Side>,
}

/// One parsed CSV file of the toolbox: `// key=value` comments, header, rows.
struct ToolboxFile {
    path: PathBuf,
    /// `key=value` pairs of the `//` lines, with their line.
    comments: Vec<(String, String, u64)>,
    /// Line number and text of each data row.
    rows: Vec<(u64, String)>,
    header_line: u64,
    names: Vec<String>,
    last_line: u64,
}

impl ToolboxFile {
    fn read(path: &Path) -> Result<Self, ImportError> {
        let lines = read_lines(path)?;
        let mut comments = Vec::new();
        let mut header: Option<(u64, String)> = None;
        let mut rows = Vec::new();
        for (n, text) in &lines {
            let trimmed = text.trim();
            if let Some(c) = trimmed.strip_prefix("//") {
                comments.extend(c.split_whitespace().filter_map(|kv| {
                    kv.split_once('=')
                        .map(|(k, v)| (k.to_string(), v.to_string(), *n))
                }));
            } else if trimmed.is_empty() {
                continue;
            } else if header.is_none() {
                header = Some((*n, trimmed.to_string()));
            } else {
                rows.push((*n, trimmed.to_string()));
            }
        }
        let last_line = lines.last().map_or(1, |(n, _)| *n);
        let Some((header_line, text)) = header else {
            return Err(ImportError::line(
                path,
                last_line,
                "no header row (the file is empty or holds only `//` comments)",
                "a header row such as `ori_1,ori_2,...` followed by one row per sample",
            ));
        };
        let names = super::split_cells(&text)
            .into_iter()
            .map(String::from)
            .collect();
        if rows.is_empty() {
            return Err(ImportError::line(
                path,
                last_line,
                "no data rows",
                "at least one row after the header",
            ));
        }
        Ok(ToolboxFile {
            path: path.to_path_buf(),
            comments,
            rows,
            header_line,
            names,
            last_line,
        })
    }

    fn comment(&self, key: &str) -> Option<&str> {
        self.comments
            .iter()
            .find(|(k, _, _)| k == key)
            .map(|(_, v, _)| v.as_str())
    }

    /// Line of a comment key (1 when absent).
    fn comment_line(&self, key: &str) -> u64 {
        self.comments
            .iter()
            .find(|(k, _, _)| k == key)
            .map_or(1, |(_, _, n)| *n)
    }

    fn header(&self) -> Header<'_> {
        Header {
            path: &self.path,
            line: self.header_line,
            names: self.names.clone(),
        }
    }

    /// The `fs=` comment, checked.
    fn sample_rate(&self) -> Result<Option<f64>, ImportError> {
        let Some(v) = self.comment("fs") else {
            return Ok(None);
        };
        match v.parse::<f64>() {
            Ok(fs) if fs.is_finite() && fs > 0.0 => Ok(Some(fs)),
            _ => Err(ImportError::line(
                &self.path,
                self.comment_line("fs"),
                format!("comment `fs={v}`"),
                "`// fs=<sample rate in Hz>` with a positive number",
            )),
        }
    }

    /// Reads groups of numeric columns `{stem}_1..{stem}_K` for every row; a
    /// group is `None` in a row where any of its cells is empty or `NaN`.
    fn groups<const K: usize>(
        &self,
        stem: &str,
        expected: &str,
    ) -> Result<Vec<Option<[f64; K]>>, ImportError> {
        let h = self.header();
        let mut cols = [0usize; K];
        for (i, c) in cols.iter_mut().enumerate() {
            *c = h.require(&format!("{stem}_{}", i + 1), expected)?;
        }
        let needed = cols.iter().copied().max().unwrap_or(0);
        self.rows
            .iter()
            .map(|(line, text)| {
                let cells = h.cells(*line, text, needed)?;
                let mut out = [0.0; K];
                for (o, &c) in out.iter_mut().zip(&cols) {
                    match h.number(*line, &cells, c, true)? {
                        Some(v) => *o = v,
                        None => return Ok(None),
                    }
                }
                Ok(Some(out))
            })
            .collect()
    }
}

/// Imports the gaittoolbox trial in `dir` with default options.
pub fn import_gaittoolbox(dir: &Path) -> Result<ImportedTrial, ImportError> {
    import_gaittoolbox_with(dir, &GaittoolboxOptions::default())
}

/// Imports the gaittoolbox trial in `dir`: 4 IMUs (Pelvis -> trunk, R_UpLeg ->
/// thigh, R_LowLeg -> shank, R_Foot -> foot, or the `L_` files of the left
/// leg; LowLeg2 is not imported) with their raw acc (m/s^2), gyr (rad/s) and
/// Xsens orientation quaternion, plus thigh/shank/foot/knee/ankle reference
/// angles from the leg's Vicon joint centres.
pub fn import_gaittoolbox_with(
    dir: &Path,
    opts: &GaittoolboxOptions,
) -> Result<ImportedTrial, ImportError> {
    if !dir.is_dir() {
        return Err(ImportError::io(
            dir,
            std::io::Error::new(
                std::io::ErrorKind::NotFound,
                "expected a folder with imu-*.csv and a Vicon file (vicon-right.csv, vicon-left.csv or vicon.csv)",
            ),
        ));
    }
    let leg = leg_files(dir, opts.leg)?;
    let vicon = ToolboxFile::read(&leg.vicon)?;
    let vicon_name = leg
        .vicon
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let n = vicon.rows.len();
    let fs = vicon.sample_rate()?.unwrap_or(100.0);
    let unit = vicon.comment("posUnit").unwrap_or("m");
    let scale = match unit {
        "m" => 1.0,
        "cm" => 0.01,
        "mm" => 0.001,
        other => {
            return Err(ImportError::line(
                &vicon.path,
                vicon.comment_line("posUnit"),
                format!("comment `posUnit={other}`"),
                "position unit `m`, `cm` or `mm`",
            ))
        }
    };
    let centre = |stem: &str| -> Result<Vec<Option<Vector3<f64>>>, ImportError> {
        let g = vicon.groups::<3>(
            stem,
            "joint-centre columns PELV_1..3 and the leg's FEP, FEO, TIO, TOE _1..3 (R... right, L... left)",
        )?;
        Ok(g.into_iter()
            .map(|p| p.map(|p| Vector3::from(p) * scale))
            .collect())
    };
    let joint_centres = JointCentres {
        pelvis: centre("PELV")?,
        hip: centre(&leg.column("FEP"))?,
        knee: centre(&leg.column("FEO"))?,
        ankle: centre(&leg.column("TIO"))?,
        toe: centre(&leg.column("TOE"))?,
    };

    let mut imus: Vec<Vec<ImuSample>> = Vec::new();
    for stem in &leg.imu {
        let file = ToolboxFile::read(&dir.join(format!("imu-{stem}.csv")))?;
        if let Some(f) = file.sample_rate()? {
            if (f - fs).abs() > 1e-9 * fs {
                return Err(ImportError::line(
                    &file.path,
                    file.comment_line("fs"),
                    format!("sample rate fs={f}"),
                    format!("the rate of {vicon_name} ({fs} Hz)"),
                ));
            }
        }
        if file.rows.len() != n {
            return Err(ImportError::line(
                &file.path,
                file.last_line,
                format!("{} samples", file.rows.len()),
                format!("{n} samples, as many as {vicon_name} (sample k of every file is the same instant)"),
            ));
        }
        let expected = "Xsens columns ori_1..4, acc_1..3, gyr_1..3";
        let quat = file.groups::<4>("ori", expected)?;
        let acc = file.groups::<3>("acc", expected)?;
        let gyr = file.groups::<3>("gyr", expected)?;
        let mut samples = Vec::with_capacity(n);
        for k in 0..n {
            let q = match quat[k] {
                Some(q) => {
                    let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
                    if norm < 1e-6 {
                        let h = file.header();
                        let col = h.require("ori_1", expected)?;
                        return Err(h.bad_cell(
                            file.rows[k].0,
                            col,
                            "0,0,0,0",
                            "a non-zero orientation quaternion",
                        ));
                    }
                    Some(q.map(|c| c / norm))
                }
                None => None,
            };
            samples.push(ImuSample {
                acc: acc[k].map(Vector3::from),
                gyr: gyr[k].map(Vector3::from),
                quat: q,
                ..Default::default()
            });
        }
        imus.push(samples);
    }

    let reference = sagittal_reference(&joint_centres, fs, &opts.reference);
    let has_foot = reference.foot_offset.is_some();
    let mut records = Vec::with_capacity(n);
    for k in 0..n {
        let mut r = Record::default();
        r.sample.t = k as f64 / fs;
        let src = k as i64 + i64::from(opts.shift_imu_samples);
        if (0..n as i64).contains(&src) {
            for (s, imu) in imus.iter().enumerate() {
                r.sample.imu[s] = imu[src as usize];
            }
        }
        let seg = &mut r.reference.segment;
        seg[Segment::Thigh.index()] = reference.thigh[k];
        seg[Segment::Shank.index()] = reference.shank[k];
        seg[Segment::Foot.index()] = reference.foot[k];
        let joint = |j: Joint, seg: &[Option<f64>; 4]| {
            let (p, d) = j.segments();
            Some(seg[p.index()]? - seg[d.index()]?)
        };
        r.reference.joint[Joint::Knee.index()] = joint(Joint::Knee, seg);
        r.reference.joint[Joint::Ankle.index()] = joint(Joint::Ankle, seg);
        r.reference.speed = reference.walking_speed[k];
        records.push(r);
    }

    let mut layout = TrialLayout {
        acc: [true; 4],
        gyr: [true; 4],
        quat: [true; 4],
        ..Default::default()
    };
    layout.segment_ref[Segment::Thigh.index()] = true;
    layout.segment_ref[Segment::Shank.index()] = true;
    layout.segment_ref[Segment::Foot.index()] = has_foot;
    layout.joint_ref[Joint::Knee.index()] = true;
    layout.joint_ref[Joint::Ankle.index()] = has_foot;
    layout.speed_ref = true;

    let p = &opts.reference;
    let mut meta = TrialMeta::trial_v1();
    let orig = vicon.comment("origFName").unwrap_or("unknown");
    let idx = vicon.comment("idx").unwrap_or("unknown");
    meta.set(
        "source",
        format!("gaittoolbox {orig} (idx {idx}) from {}", dir.display()),
    );
    meta.set("sample_rate_hz", fmt(fs, 0));
    meta.set("leg", leg.side.name());
    meta.set("g", "9.81");
    let [_, up, low, foot] = &leg.imu;
    let mut map = format!(
        "trunk=imu-Pelvis thigh=imu-{up} shank=imu-{low} foot=imu-{foot} (imu-{low}2, mag_* and step-detect.csv not imported)"
    );
    if vicon_name != "vicon-right.csv" {
        map += &format!("; Vicon {vicon_name}");
    }
    if leg.both_legs {
        let other = match leg.side {
            Side::Left => "right",
            Side::Right => "left",
        };
        map += &format!("; the folder also holds the {other} leg (import --leg {other})");
    }
    meta.set("segment_map", map);
    meta.set(
        "units",
        format!("acc m/s^2 and gyr rad/s as recorded (no conversion); Vicon positions {unit} scaled by {scale} to m"),
    );
    meta.set(
        "imu_frame",
        "raw sensor frames (unaligned); quat = Xsens on-board orientation sensor->world (world z up, w first), normalised",
    );
    meta.set(
        "synchronisation",
        format!(
            "IMU and Vicon sample k taken as the same instant; IMU advanced by {} samples (measured lag about 2 samples, docs/IMPORTERS.md)",
            opts.shift_imu_samples
        ),
    );
    meta.set("imu_shift_samples", opts.shift_imu_samples);
    meta.set(
        "reference_method",
        format!(
            "heading-following sagittal plane: forward = horizontal direction of the PELV velocity averaged over {} s; theta = atan2(forward, -up) of the proximal->distal vector (thigh {hip}->{knee}, shank {knee}->{ankle}, foot {ankle}->{toe} minus foot_offset); knee = thigh - shank, ankle = shank - foot",
            fmt(p.heading_window_s, 2),
            hip = leg.column("FEP"),
            knee = leg.column("FEO"),
            ankle = leg.column("TIO"),
            toe = leg.column("TOE"),
        ),
    );
    let ranges: Vec<String> = reference
        .straight
        .iter()
        .map(|r| format!("{}..{}", r.start, r.end))
        .collect();
    let times: Vec<String> = reference
        .straight
        .iter()
        .map(|r| {
            format!(
                "{}..{}",
                fmt(r.start as f64 / fs, 2),
                fmt(r.end as f64 / fs, 2)
            )
        })
        .collect();
    meta.set("straight_segments", ranges.join(","));
    meta.set("straight_segments_s", times.join(","));
    meta.set(
        "straight_rule",
        format!(
            "half-open sample ranges where smoothed pelvis speed >= {} m/s and |heading rate| <= {} deg/s for >= {} s; references outside them (start, turn, stop) are computed but not meaningful",
            p.min_speed,
            fmt(p.max_heading_rate.to_degrees(), 0),
            p.min_straight_s
        ),
    );
    meta.set(
        "speed_ref",
        "walking speed on the straight parts only (empty elsewhere): the Vicon PELV velocity (central difference, per sample) along the heading; its mean over a stride is the distance the pelvis walked over it divided by the stride time",
    );
    match reference.foot_offset {
        Some(off) => {
            meta.set("foot_offset_rad", fmt(off, 5));
            meta.set("foot_offset_deg", fmt(off.to_degrees(), 2));
        }
        None => meta.set(
            "foot_ref",
            "absent: too few foot-flat samples to fix the foot zero",
        ),
    }
    meta.set(
        "foot_zero_rule",
        format!(
            "median raw foot angle over {} foot-flat samples (toe and ankle speed < {} m/s) on the straight parts: foot flat on level floor = standing pose",
            reference.foot_flat_samples, p.foot_flat_speed
        ),
    );
    meta.set(
        "trunk_ref",
        "absent: the Vicon pelvis orientation agrees poorly with the pelvis IMU (r = 0.5 on the medio-lateral rate), and there is no standing period to fix its zero; hence no hip_ref",
    );
    Ok(ImportedTrial {
        meta,
        layout,
        records,
    })
}
