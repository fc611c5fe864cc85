//! The two metadata keys of a leg length: `lowback-speed` documents
//! `# leg_length:` (docs/GAIT_EVENTS.md), `imm-bslip` `# leg_length_m:`
//! (docs/GAIT_IMM.md). Each method reads both, its own key first (a
//! fresh-user audit, session 28: a trial stating one key was read by one
//! method and not the other); a trial stating both with different values
//! gets a warning, and each method keeps its own key.

use limbfuse_io::TrialMeta;

use crate::MethodName;

/// `lowback-speed`'s key (m; an optional `m` unit).
pub const LOWBACK_KEY: &str = "leg_length";
/// `imm-bslip`'s key (m).
pub const IMM_KEY: &str = "leg_length_m";

/// The keys `method` reads, its own first; `None` for methods that read
/// no leg length from the metadata.
pub fn keys_of(method: MethodName) -> Option<[&'static str; 2]> {
    match method {
        MethodName::LowbackSpeed => Some([LOWBACK_KEY, IMM_KEY]),
        MethodName::ImmBslip => Some([IMM_KEY, LOWBACK_KEY]),
        _ => None,
    }
}

/// The first of `keys` the trial states, with its text.
pub fn stated<'m>(meta: &'m TrialMeta, keys: [&'static str; 2]) -> Option<(&'static str, &'m str)> {
    keys.into_iter().find_map(|k| meta.get(k).map(|v| (k, v)))
}

/// A length in metres as the keys take it: a number with an optional `m`.
pub fn metres(text: &str) -> Option<f64> {
    text.trim().trim_end_matches('m').trim().parse().ok()
}

/// The warning for a trial (`label`) stating both keys with different
/// values, for `method` (which keeps its own key); `None` otherwise.
pub fn conflict_warning(method: MethodName, meta: &TrialMeta, label: &str) -> Option<String> {
    let [own, other] = keys_of(method)?;
    let (a, b) = (meta.get(own)?, meta.get(other)?);
    let differ = match (metres(a), metres(b)) {
        (Some(x), Some(y)) => (x - y).abs() > 1e-9 * x.abs().max(y.abs()),
        _ => a.trim() != b.trim(),
    };
    differ.then(|| {
        format!(
            "warning: {label} states `# {own}: {}` and `# {other}: {}`: `{}` reads `# {own}:`, its \
             own key (docs/GAIT_EVENTS.md for `leg_length`, docs/GAIT_IMM.md for `leg_length_m`)",
            a.trim(),
            b.trim(),
            method.name()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_method_reads_its_own_key_first_and_warns_on_a_conflict() {
        let mut meta = TrialMeta::new();
        meta.set(IMM_KEY, "0.95");
        let lowback = keys_of(MethodName::LowbackSpeed).unwrap();
        assert_eq!(stated(&meta, lowback), Some((IMM_KEY, "0.95")));
        meta.set(LOWBACK_KEY, "0.95 m");
        assert_eq!(stated(&meta, lowback), Some((LOWBACK_KEY, "0.95 m")));
        assert!(conflict_warning(MethodName::LowbackSpeed, &meta, "t.csv").is_none());
        meta.set(LOWBACK_KEY, "0.9");
        let w = conflict_warning(MethodName::ImmBslip, &meta, "t.csv").unwrap();
        assert!(w.contains("`imm-bslip` reads `# leg_length_m:`"), "{w}");
        assert!(conflict_warning(MethodName::Mjls, &meta, "t.csv").is_none());
    }
}
