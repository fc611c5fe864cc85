//! The trial body of `imm-bslip` and the library's rescaling to it
//! (issue 19 item 1; docs/GAIT_IMM.md, "Continuous gait family").
//!
//! Each of mass and leg length comes from, in order: the flags / parameter
//! file (`--leg-length`, `--mass`), the trial's metadata keys `# leg_length_m:` and
//! `# body_mass_kg:` (SPEC addition), or a `# model:` line that describes a
//! B-SLIP in words ("... mass 70.0 kg ... rest length 0.95 m ...", as the
//! shared independent B-SLIP trials do); gravity is the trial's `# g:`.
//! A library built for another body is rescaled by Froude similarity
//! ([`GaitTemplate::rescaled_to_body`]) with a message; a trial whose body
//! differs from the library's in mass or gravity but gives no leg length
//! cannot be rescaled and is an error.

use limbfuse_io::TrialMeta;
use limbfuse_models::bslip::{BslipParams, GaitTemplate};

use crate::body_ranges::{within, LEG_LENGTH_M, MASS_KG};
use crate::MethodError;

/// The trial's body as far as it is known, and where it came from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrialBody {
    /// Mass (kg).
    pub mass: Option<f64>,
    /// Leg rest length (m).
    pub leg_length: Option<f64>,
    /// Gravity (m/s^2).
    pub gravity: f64,
    /// Where the leg length (or mass) came from.
    pub source: &'static str,
}

fn bad(what: String) -> MethodError {
    MethodError::ImmParams(what)
}

fn positive(name: &str, v: f64) -> Result<f64, MethodError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(bad(format!(
            "{name}: expected a positive number, found {v}"
        )))
    }
}

/// `v` when within `(lo, hi)` ([`crate::body_ranges`]); else an error
/// naming `name`.
fn plausible(name: &str, v: f64, (lo, hi): (f64, f64), unit: &str) -> Result<f64, MethodError> {
    within(v, (lo, hi)).ok_or_else(|| {
        bad(format!(
            "{name} {}: expected a human body's value, {lo} to {hi} {unit}",
            crate::error::shown(v)
        ))
    })
}

fn meta_number(meta: &TrialMeta, key: &str) -> Result<Option<f64>, MethodError> {
    match meta.get(key) {
        None => Ok(None),
        Some(text) => {
            let v = text.trim().parse::<f64>().map_err(|_| {
                bad(format!(
                    "trial metadata `# {key}: {text}`: expected a number"
                ))
            })?;
            positive(&format!("# {key}"), v).map(Some)
        }
    }
}

/// The number right before `unit` after the words `before` in `text`
/// (`"point mass 70.0 kg"`, `"mass"`, `"kg"` -> 70).
fn number_after(text: &str, before: &str, unit: &str) -> Option<f64> {
    let rest = &text[text.find(before)? + before.len()..];
    let mut words = rest.split_whitespace();
    let value = words.next()?.parse::<f64>().ok()?;
    let u = words.next()?.trim_end_matches([',', ';', '.']);
    (u == unit && value.is_finite() && value > 0.0).then_some(value)
}

/// The trial's body from the flags (`mass`, `leg_length`) and its metadata,
/// each quantity from the first source that has it.
pub fn trial_body(
    mass: Option<f64>,
    leg_length: Option<f64>,
    meta: &TrialMeta,
) -> Result<TrialBody, MethodError> {
    if let Some(m) = mass {
        plausible("--mass", positive("--mass", m)?, MASS_KG, "kg")?;
    }
    if let Some(l) = leg_length {
        plausible(
            "--leg-length",
            positive("--leg-length", l)?,
            LEG_LENGTH_M,
            "m",
        )?;
    }
    let model = meta.get("model").filter(|t| t.contains("SLIP"));
    let key_mass = meta_number(meta, "body_mass_kg")?
        .map(|m| plausible("trial metadata # body_mass_kg", m, MASS_KG, "kg"))
        .transpose()?;
    // `# leg_length_m:`, else lowback-speed's `# leg_length:` (an optional
    // `m` unit; crate::leg_length_keys).
    let key_leg = match meta_number(meta, crate::leg_length_keys::IMM_KEY)? {
        Some(l) => Some(plausible(
            "trial metadata # leg_length_m",
            l,
            LEG_LENGTH_M,
            "m",
        )?),
        None => match meta.get(crate::leg_length_keys::LOWBACK_KEY) {
            None => None,
            Some(text) => {
                let l = crate::leg_length_keys::metres(text).ok_or_else(|| {
                    bad(format!(
                        "trial metadata `# leg_length: {text}`: expected a number (m)"
                    ))
                })?;
                let l = positive("# leg_length", l)?;
                Some(plausible(
                    "trial metadata # leg_length",
                    l,
                    LEG_LENGTH_M,
                    "m",
                )?)
            }
        },
    };
    let model_mass = model.and_then(|t| number_after(t, "mass", "kg"));
    let model_leg = model.and_then(|t| number_after(t, "rest length", "m"));
    let source = if leg_length.is_some() || (mass.is_some() && key_leg.or(model_leg).is_none()) {
        "--leg-length / --mass"
    } else if key_leg.is_some() && meta.get(crate::leg_length_keys::IMM_KEY).is_none() {
        "# body_mass_kg / # leg_length"
    } else if key_leg.is_some() || (key_mass.is_some() && model_leg.is_none()) {
        "# body_mass_kg / # leg_length_m"
    } else {
        "# model"
    };
    Ok(TrialBody {
        mass: mass.or(key_mass).or(model_mass),
        leg_length: leg_length.or(key_leg).or(model_leg),
        gravity: meta.gravity().map_err(MethodError::Metadata)?,
        source,
    })
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

fn describe(b: &BslipParams) -> String {
    format!(
        "{} kg, l0 {} m, g {} m/s^2",
        b.mass, b.rest_length, b.gravity
    )
}

/// The library's templates for the trial body: unchanged when the body is
/// unknown or the library's, else rescaled (with the message to show).
/// Errors when the body differs but its leg length is unknown.
pub fn fit_library(
    templates: Vec<GaitTemplate>,
    body: &TrialBody,
) -> Result<(Vec<GaitTemplate>, Option<String>), MethodError> {
    let Some(first) = templates.first() else {
        return Ok((templates, None));
    };
    let lib = first.body;
    let Some(leg) = body.leg_length else {
        let mass_differs = body.mass.is_some_and(|m| !same(m, lib.mass));
        if mass_differs || !same(body.gravity, lib.gravity) {
            return Err(bad(format!(
                "the trial's body ({} kg, g {} m/s^2; from {}) is not the library's ({}) and its leg \
                 length is unknown: cannot rescale the library (give --leg-length M or the trial \
                 metadata `# leg_length_m:`, or build a library for this body)",
                body.mass.map_or("?".to_string(), |m| m.to_string()),
                body.gravity,
                body.source,
                describe(&lib)
            )));
        }
        return Ok((templates, None));
    };
    let target = BslipParams {
        mass: body.mass.unwrap_or(lib.mass),
        rest_length: leg,
        gravity: body.gravity,
        stiffness: lib.stiffness,
    };
    if same(target.mass, lib.mass)
        && same(target.rest_length, lib.rest_length)
        && same(target.gravity, lib.gravity)
    {
        return Ok((templates, None));
    }
    let scaled = templates
        .iter()
        .map(|t| t.rescaled_to_body(&target))
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| {
            bad(format!(
                "cannot rescale the library to {}",
                describe(&target)
            ))
        })?;
    let note = format!(
        "imm-bslip: library built for {}; trial body {} (from {}{}): library rescaled by Froude \
         similarity (speeds {:.3}-{:.3} m/s)",
        describe(&lib),
        describe(&target),
        body.source,
        if body.mass.is_none() {
            ", mass kept"
        } else {
            ""
        },
        scaled.first().map_or(0.0, |t| t.speed),
        scaled.last().map_or(0.0, |t| t.speed),
    );
    Ok((scaled, Some(note)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn meta(lines: &[(&str, &str)]) -> TrialMeta {
        let mut m = TrialMeta::new();
        for (k, v) in lines {
            m.set(*k, v);
        }
        m
    }

    #[test]
    fn body_from_flags_keys_or_the_model_line() {
        let model = "3D B-SLIP: point mass 70.0 kg, two massless linear spring legs, rest length 0.95 m, stiffness 14847.1 N/m";
        let b = trial_body(None, None, &meta(&[("model", model)])).unwrap();
        assert_eq!((b.mass, b.leg_length), (Some(70.0), Some(0.95)));
        let b = trial_body(
            None,
            None,
            &meta(&[("leg_length_m", "0.9"), ("model", model)]),
        )
        .unwrap();
        assert_eq!((b.mass, b.leg_length), (Some(70.0), Some(0.9)));
        let b = trial_body(Some(60.0), None, &meta(&[("model", model)])).unwrap();
        assert_eq!((b.mass, b.leg_length), (Some(60.0), Some(0.95)));
        let b = trial_body(None, Some(1.1), &meta(&[("body_mass_kg", "50")])).unwrap();
        assert_eq!((b.mass, b.leg_length), (Some(50.0), Some(1.1)));
        let b = trial_body(None, None, &meta(&[("model", "knee: mass 3 kg")])).unwrap();
        assert_eq!((b.mass, b.leg_length), (None, None));
        let e = trial_body(None, None, &meta(&[("leg_length_m", "long")])).unwrap_err();
        assert!(e.to_string().contains("leg_length_m: long"), "{e}");
        assert!(trial_body(None, Some(-1.0), &TrialMeta::new()).is_err());
        // absurd but finite bodies are refused, naming the flag or the key
        let e = trial_body(None, Some(1e300), &TrialMeta::new()).unwrap_err();
        assert!(e.to_string().contains("--leg-length 1e300"), "{e}");
        let e = trial_body(Some(5000.0), None, &TrialMeta::new()).unwrap_err();
        assert!(e.to_string().contains("--mass 5000"), "{e}");
        let e = trial_body(None, None, &meta(&[("leg_length_m", "3")])).unwrap_err();
        assert!(e.to_string().contains("# leg_length_m 3"), "{e}");
    }
}
