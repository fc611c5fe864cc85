//! The segment-angle filters of papers 000/001 as methods: `local`, `mjls`,
//! `global`, with the segment-filter parameter file
//! ([`crate::segment_params`], docs/TUNING.md).

use std::path::Path;

use limbfuse_core::Estimator;
use limbfuse_io::{TrialLayout, TrialMeta};

use crate::method_def::{MethodDef, MethodInfo};
use crate::segment_params::{parse_params, to_toml, FilterMethod, FilterParams, Preset};
use crate::{ChannelNeeds, MethodError, MethodFlags};

fn resolve(m: FilterMethod, file: Option<(&str, &Path)>) -> Result<FilterParams, MethodError> {
    Ok(match file {
        Some((text, path)) => parse_params(text, path, m)?,
        None => FilterParams::preset(m, Preset::Default),
    })
}

fn build(p: &FilterParams) -> Result<Box<dyn Estimator + Send>, MethodError> {
    Ok(p.build()?)
}

fn default_file(m: FilterMethod) -> String {
    to_toml(&FilterParams::preset(m, Preset::Default), &[])
}

const FOUR_IMUS_WHY: &str = "estimates all four segments from their IMUs";

macro_rules! segment_method {
    ($(#[$doc:meta])* $name:ident, $filter:expr, $info:expr) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy)]
        pub struct $name;

        impl MethodDef for $name {
            const INFO: MethodInfo = $info;
            type Settings = FilterParams;

            fn resolve(
                file: Option<(&str, &Path)>,
                _: &MethodFlags,
            ) -> Result<FilterParams, MethodError> {
                resolve($filter, file)
            }

            fn build(
                p: &FilterParams,
                _: &TrialMeta,
                _: &TrialLayout,
            ) -> Result<Box<dyn Estimator + Send>, MethodError> {
                build(p)
            }

            fn default_file() -> String {
                default_file($filter)
            }
        }
    };
}

segment_method!(
    /// `local`: matricial local KF (001 eqs 1-6, 14-18).
    LocalMethod,
    FilterMethod::Local,
    MethodInfo {
        in_walking_demo: true,
        ..MethodInfo::new(
            "local",
            "papers 000/001: per-segment error-state KFs (matricial local)",
            "the four IMUs (aligned)",
            "segment-filter parameter file (docs/TUNING.md): preset, noise densities, gates",
        )
        .needing(ChannelNeeds::FOUR_IMUS, FOUR_IMUS_WHY)
        .reading_aligned_frames()
    }
);

segment_method!(
    /// `mjls`: Markov-jump KF (000).
    MjlsMethod,
    FilterMethod::Mjls,
    MethodInfo {
        in_walking_demo: true,
        needs_hint: "; use `local` or `global` on trials without encoders",
        ..MethodInfo::new(
            "mjls",
            "papers 000/001: Markov-jump KF, 4 IMUs + 3 encoders",
            "the four IMUs (aligned) and the hip, knee and ankle encoders",
            "segment-filter parameter file (docs/TUNING.md); encoder_sigma, when_unreliable",
        )
        .needing(
            ChannelNeeds {
                encoder: [true; 3],
                ..ChannelNeeds::FOUR_IMUS
            },
            "needs the four IMUs and the joint encoders (its output rows are the most reliable accelerometer plus hip, knee and ankle encoders)",
        )
        .reading_aligned_frames()
    }
);

segment_method!(
    /// `global`: matricial global KF (001).
    GlobalMethod,
    FilterMethod::Global,
    MethodInfo {
        in_walking_demo: true,
        relative_rows: true,
        ..MethodInfo::new(
            "global",
            "paper 001: matricial global KF, 4 IMUs + relative rows + encoders",
            "the four IMUs (aligned); encoders when present",
            "segment-filter parameter file (docs/TUNING.md); relative_sigma, min_reliable",
        )
        .needing(ChannelNeeds::FOUR_IMUS, FOUR_IMUS_WHY)
        .reading_aligned_frames()
    }
);
