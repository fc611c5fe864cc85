//! Column names written another way than SPEC section 2 spells them (a
//! fresh-recording audit, session 42): `Time (s)` or `timestamp` for `t`,
//! `Thigh_Gyr_X`, `thigh-gyr-x` or `thigh_gyr_x [deg/s]` for `thigh_gyr_x`. An unknown column is
//! ignored, as it must be (a file may carry anything else), so such a file
//! was read without the channel and a method then said only that the trial
//! has no `thigh_gyr_x` column; the missing `t` was "missing required
//! column `t`". The reader now names the column that is the channel.

use limbfuse_core::Side;

use crate::layout::TrialLayout;

/// `name` as SPEC spells a column: trimmed, lowercase, with `_` for spaces,
/// `-` and `.`.
fn spelled(name: &str) -> String {
    name.trim()
        .to_lowercase()
        .chars()
        .map(|c| if matches!(c, ' ' | '-' | '.') { '_' } else { c })
        .collect()
}

/// Every column name a trial file can hold (either leg's other-leg columns).
fn known_columns() -> Vec<String> {
    let mut names = Vec::new();
    for leg in [Side::Right, Side::Left] {
        let all = TrialLayout {
            leg,
            acc: [true; 4],
            gyr: [true; 4],
            quat: [true; 4],
            other_acc: [true; 4],
            other_gyr: [true; 4],
            encoder: [true; 3],
            stim: [true; 4],
            motor_torque: [true; 3],
            com_meas: [true; 6],
            segment_ref: [true; 4],
            joint_ref: [true; 3],
            com_pos: true,
            com_vel: true,
            phase_ref: true,
            contact_ref: [true; 2],
            speed_ref: true,
        };
        names.extend(all.column_names());
    }
    names.sort();
    names.dedup();
    names
}

/// `name` without a trailing unit in brackets or parentheses
/// (`thigh_gyr_x [deg/s]`, `knee_enc (rad)`).
fn without_unit(name: &str) -> &str {
    let n = name.trim_end();
    match (n.ends_with(')') || n.ends_with(']'))
        .then(|| n.rfind(['(', '[']))
        .flatten()
    {
        Some(at) => n[..at].trim_end(),
        None => n,
    }
}

/// The first header cell (1-based column, name) that is a known trial
/// column written another way (another case, `-` or `.` for `_`, a unit
/// after it) while the column itself is absent, with the name SPEC gives it.
pub(crate) fn misspelt_channel(header: &[String]) -> Option<(usize, String, String)> {
    let known = known_columns();
    header.iter().enumerate().find_map(|(i, h)| {
        let s = spelled(without_unit(h));
        (s != *h && known.contains(&s) && !header.contains(&s)).then(|| (i + 1, h.clone(), s))
    })
}

/// What to add to "missing required column `t`" when another column looks
/// like the time: `time`, `Time (s)`, `timestamp`, `T`.
pub(crate) fn time_column_hint(header: &[String]) -> String {
    let time_like = |h: &str| {
        let s = spelled(h);
        let word: String = s
            .split(['(', '['])
            .next()
            .unwrap_or("")
            .trim_matches('_')
            .to_string();
        matches!(
            word.as_str(),
            "t" | "time" | "times" | "time_s" | "t_s" | "timestamp" | "time_stamp" | "seconds"
        )
    };
    match header.iter().find(|h| time_like(h)) {
        Some(h) => format!(
            "; column `{h}` looks like it: name it `t` (seconds from any origin, strictly \
             increasing; SPEC section 2)"
        ),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(names: &[&str]) -> Vec<String> {
        names.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn a_channel_in_another_case_or_with_dashes_is_named() {
        let h = header(&["t", "Thigh_Gyr_X", "thigh_gyr_y", "thigh_gyr_z"]);
        assert_eq!(
            misspelt_channel(&h),
            Some((2, "Thigh_Gyr_X".into(), "thigh_gyr_x".into()))
        );
        let h = header(&["t", "knee-enc", "foot_left_acc_x"]);
        assert_eq!(misspelt_channel(&h).map(|m| m.2), Some("knee_enc".into()));
        // a unit after the name
        for name in [
            "thigh_gyr_x [deg/s]",
            "Thigh_Gyr_X (rad/s)",
            "knee_enc(rad)",
        ] {
            let found = misspelt_channel(&header(&["t", name])).map(|m| m.1);
            assert_eq!(found.as_deref(), Some(name));
        }
        // the spelled name present, or nothing like a channel: nothing said
        assert_eq!(
            misspelt_channel(&header(&["t", "Knee_Enc", "knee_enc"])),
            None
        );
        assert_eq!(misspelt_channel(&header(&["t", "Note", "GPS lat"])), None);
    }

    #[test]
    fn time_like_columns_are_named_and_others_are_not() {
        for name in ["time", "Time (s)", "TIMESTAMP", "T", "time[s]", "Time_s"] {
            let hint = time_column_hint(&header(&["acc", name]));
            assert!(
                hint.contains(&format!("column `{name}` looks like it")),
                "{name}: {hint}"
            );
        }
        for name in ["timer_count", "tau", "temperature"] {
            assert_eq!(time_column_hint(&header(&[name, "x"])), "", "{name}");
        }
    }
}
