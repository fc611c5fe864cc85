//! Which leg a gaittoolbox folder holds, and its files.
//!
//! The toolbox names a leg's Xsens files `imu-R_UpLeg.csv`, `imu-R_LowLeg.csv`,
//! `imu-R_Foot.csv` (left: `L_`), and its Vicon joint centres `RFEP` (hip),
//! `RFEO` (knee), `RTIO` (ankle), `RTOE` (toe) (left: `L...`); the pelvis
//! (`imu-Pelvis.csv`, `PELV`) is shared. The shared S02 folder holds the right
//! leg with `vicon-right.csv`; a folder of the other leg (`vicon-left.csv`) or
//! of both (the toolbox's own `vicon.csv` carries both legs' columns) imports
//! the same way. A folder with both legs' IMU files imports the right one
//! unless the left is asked for.

use std::path::{Path, PathBuf};

use limbfuse_core::Side;

use super::ImportError;

/// A leg's files in a gaittoolbox folder.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct LegFiles {
    /// The leg.
    pub side: Side,
    /// IMU file stems per limbfuse segment (trunk, thigh, shank, foot).
    pub imu: [String; 4],
    /// The Vicon file with this leg's joint centres.
    pub vicon: PathBuf,
    /// `R` or `L`: the prefix of the leg's Vicon columns.
    pub prefix: &'static str,
    /// Whether the folder also holds the other leg's IMU files.
    pub both_legs: bool,
}

impl LegFiles {
    /// The leg's Vicon column stem: `FEP` -> `RFEP` / `LFEP`.
    pub fn column(&self, joint: &str) -> String {
        format!("{}{joint}", self.prefix)
    }
}

fn prefix(side: Side) -> &'static str {
    match side {
        Side::Left => "L",
        Side::Right => "R",
    }
}

fn imu_stems(side: Side) -> [String; 4] {
    let p = prefix(side);
    [
        "Pelvis".to_string(),
        format!("{p}_UpLeg"),
        format!("{p}_LowLeg"),
        format!("{p}_Foot"),
    ]
}

fn has_leg(dir: &Path, side: Side) -> bool {
    imu_stems(side)[1..]
        .iter()
        .all(|s| dir.join(format!("imu-{s}.csv")).is_file())
}

/// Whether the first line that is neither empty nor a `//` comment (the
/// header) names `column`.
fn header_has(path: &Path, column: &str) -> bool {
    // (`read_lines` strips `\r` and a byte-order mark, as for the import)
    let Ok(lines) = super::read_lines(path) else {
        return false;
    };
    lines
        .iter()
        .map(|(_, l)| l.trim())
        .find(|l| !l.is_empty() && !l.starts_with("//"))
        .is_some_and(|h| h.split(',').any(|c| c.trim() == column))
}

/// The leg `requested` (or the one the folder holds: the right when it
/// holds both) and its files.
pub(super) fn leg_files(dir: &Path, requested: Option<Side>) -> Result<LegFiles, ImportError> {
    let (right, left) = (has_leg(dir, Side::Right), has_leg(dir, Side::Left));
    let side = match (requested, right, left) {
        (Some(s), ..) => s,
        (None, true, _) => Side::Right,
        (None, false, true) => Side::Left,
        (None, false, false) => {
            return Err(ImportError::io(
                dir,
                std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    "expected a gaittoolbox folder: imu-Pelvis.csv with imu-R_UpLeg.csv, \
                     imu-R_LowLeg.csv, imu-R_Foot.csv (right leg) or imu-L_UpLeg.csv, \
                     imu-L_LowLeg.csv, imu-L_Foot.csv (left leg), and a Vicon file \
                     (vicon-right.csv, vicon-left.csv or vicon.csv)",
                ),
            ))
        }
    };
    let p = prefix(side);
    let hip = format!("{p}FEP_1");
    let mut candidates = vec![
        dir.join(format!("vicon-{}.csv", side.name())),
        dir.join("vicon.csv"),
    ];
    let mut others: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| ImportError::io(dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("vicon") && n.ends_with(".csv"))
        })
        .collect();
    others.sort();
    candidates.extend(others);
    let vicon = candidates
        .iter()
        .find(|c| c.is_file() && header_has(c, &hip))
        .cloned()
        .ok_or_else(|| {
            ImportError::io(
                dir,
                std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    format!(
                        "no Vicon file with the {} leg's joint centres (column {hip}): looked for \
                         vicon-{}.csv, vicon.csv and any vicon*.csv",
                        side.name(),
                        side.name()
                    ),
                ),
            )
        })?;
    Ok(LegFiles {
        side,
        imu: imu_stems(side),
        vicon,
        prefix: p,
        both_legs: right && left,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn touch(dir: &Path, name: &str, text: &str) {
        std::fs::write(dir.join(name), text).unwrap();
    }

    #[test]
    fn the_leg_comes_from_the_files_and_the_vicon_file_from_its_columns() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path();
        // Nothing: an error naming both legs' files.
        let e = leg_files(p, None).unwrap_err().to_string();
        assert!(
            e.contains("imu-L_Foot.csv") && e.contains("imu-R_Foot.csv"),
            "{e}"
        );
        for s in ["Pelvis", "L_UpLeg", "L_LowLeg", "L_Foot"] {
            touch(p, &format!("imu-{s}.csv"), "ori_1\n1\n");
        }
        // The left leg's IMUs, but no Vicon file with its columns.
        touch(p, "vicon-right.csv", "// fs=100\nPELV_1,RFEP_1\n1,2\n");
        let e = leg_files(p, None).unwrap_err().to_string();
        assert!(e.contains("LFEP_1") && e.contains("left"), "{e}");
        touch(p, "vicon.csv", "// fs=100\nPELV_1,LFEP_1,RFEP_1\n1,2,3\n");
        let l = leg_files(p, None).unwrap();
        assert_eq!((l.side, l.prefix, l.both_legs), (Side::Left, "L", false));
        assert_eq!(l.vicon, p.join("vicon.csv"));
        assert_eq!(l.imu[3], "L_Foot");
        assert_eq!(l.column("TOE"), "LTOE");
        touch(p, "vicon-left.csv", "PELV_1,LFEP_1\n1,2\n");
        assert_eq!(leg_files(p, None).unwrap().vicon, p.join("vicon-left.csv"));
        // Both legs: the right unless the left is asked for.
        for s in ["R_UpLeg", "R_LowLeg", "R_Foot"] {
            touch(p, &format!("imu-{s}.csv"), "ori_1\n1\n");
        }
        let r = leg_files(p, None).unwrap();
        assert_eq!((r.side, r.both_legs), (Side::Right, true));
        assert_eq!(r.vicon, p.join("vicon-right.csv"));
        assert_eq!(leg_files(p, Some(Side::Left)).unwrap().side, Side::Left);
    }
}
