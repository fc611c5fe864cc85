//! What the B-SLIP study examples share: a gait library searched in memory,
//! and the shared independent B-SLIP trials with the body in their
//! metadata.

use std::path::{Path, PathBuf};

use limbfuse_core::Record;
use limbfuse_io::{TrialMeta, TrialReader};
use limbfuse_methods::imm_body::{trial_body, TrialBody};
use limbfuse_models::bslip::{BslipParams, GaitTemplate};
use limbfuse_sim::bslip::library::build_library;
use limbfuse_sim::bslip::search::SearchSettings;

/// The library `gait-library build --speeds ...` builds for `body`, as
/// templates.
pub fn library(body: &BslipParams, speeds: &[f64]) -> Vec<GaitTemplate> {
    build_library(body, speeds, &SearchSettings::default(), |_, _| {})
        .expect("gait search")
        .iter()
        .map(|g| g.template(body))
        .collect()
}

/// One shared independent B-SLIP trial.
pub struct IndependentTrial {
    /// The file.
    pub path: PathBuf,
    /// Its metadata.
    pub meta: TrialMeta,
    /// Its records.
    pub records: Vec<Record>,
    /// The body from its metadata.
    pub body_source: TrialBody,
    /// That body as B-SLIP parameters (the rest from `base`).
    pub body: BslipParams,
}

/// Every `bslip-*.csv` of `data/independent-sim`, sorted by name; `None`
/// when the folder is absent.
pub fn independent_trials(data: &Path, base: BslipParams) -> Option<Vec<IndependentTrial>> {
    let dir = data.join("independent-sim");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .ok()?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("bslip-") && n.ends_with(".csv"))
        })
        .collect();
    files.sort();
    let trials = files
        .into_iter()
        .map(|path| {
            let mut reader = TrialReader::open(&path).expect("shared trial");
            let meta = reader.meta().clone();
            let mut records = Vec::new();
            while let Some(r) = reader.next_record().expect("shared trial row") {
                records.push(r);
            }
            let body_source = trial_body(None, None, &meta).expect("trial body");
            let body = BslipParams {
                mass: body_source.mass.expect("body mass in the metadata"),
                rest_length: body_source.leg_length.expect("leg length in the metadata"),
                gravity: body_source.gravity,
                ..base
            };
            IndependentTrial {
                path,
                meta,
                records,
                body_source,
                body,
            }
        })
        .collect();
    Some(trials)
}
