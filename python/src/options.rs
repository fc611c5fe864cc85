//! Keyword options from Python (`**options`): typed reads that name the
//! option in their errors, an error on any option not read, and method
//! settings (`params` as a TOML file path or a dict; the method flags).

use std::path::PathBuf;

use limbfuse_io::DiagnosticColumns;
use limbfuse_methods::{MethodFlags, MethodName, MethodSpec};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use crate::{chain_message, user_error, user_msg};

/// Whether `v` is a bool: Python's or numpy's (`numpy.bool_`, e.g. from
/// `array.any()`).
pub(crate) fn is_bool(v: &Bound<'_, PyAny>) -> bool {
    if v.is_instance_of::<PyBool>() {
        return true;
    }
    let ty = v.get_type();
    ty.module().is_ok_and(|m| m == "numpy") && ty.name().is_ok_and(|n| n == "bool" || n == "bool_")
}

/// `repr(v)` for a message, shortened (a 400-digit integer).
pub(crate) fn shown(v: &Bound<'_, PyAny>) -> String {
    let r = v.repr().map_or_else(|_| "?".to_string(), |r| r.to_string());
    if r.chars().count() > 40 {
        let head: String = r.chars().take(37).collect();
        format!("{head}...")
    } else {
        r
    }
}

/// The options of one call, read one by one.
pub struct Options<'py> {
    what: &'static str,
    dict: Option<Bound<'py, PyDict>>,
    read: Vec<&'static str>,
}

impl<'py> Options<'py> {
    /// Options of the function `what` (named in errors).
    pub fn new(what: &'static str, dict: Option<Bound<'py, PyDict>>) -> Self {
        Options {
            what,
            dict,
            read: Vec::new(),
        }
    }

    fn raw(&mut self, key: &'static str) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.read.push(key);
        match &self.dict {
            Some(d) => Ok(d.get_item(key)?.filter(|v| !v.is_none())),
            None => Ok(None),
        }
    }

    /// A finite number.
    pub fn f64(&mut self, key: &'static str) -> PyResult<Option<f64>> {
        let Some(v) = self.raw(key)? else {
            return Ok(None);
        };
        let x: f64 = if is_bool(&v) { None } else { v.extract().ok() }
            .ok_or_else(|| user_msg(format!("{}: option `{key}`: expected a number", self.what)))?;
        if !x.is_finite() {
            return Err(user_msg(format!(
                "{}: option `{key}`: expected a finite number, found {x}",
                self.what
            )));
        }
        Ok(Some(x))
    }

    /// A non-negative integer.
    pub fn u64(&mut self, key: &'static str) -> PyResult<Option<u64>> {
        let Some(v) = self.raw(key)? else {
            return Ok(None);
        };
        // (a Python int or a numpy integer, `__index__`: an audit found
        // `window=np.int64(500)` refused as "expected a non-negative integer")
        let n = if is_bool(&v) {
            None
        } else {
            v.extract::<u64>().ok()
        };
        n.map(Some).ok_or_else(|| {
            user_msg(format!(
                "{}: option `{key}`: expected a non-negative integer, found {}",
                self.what,
                shown(&v)
            ))
        })
    }

    /// A boolean.
    pub fn bool(&mut self, key: &'static str) -> PyResult<Option<bool>> {
        let Some(v) = self.raw(key)? else {
            return Ok(None);
        };
        if !is_bool(&v) {
            return Err(user_msg(format!(
                "{}: option `{key}`: expected True or False, found {}",
                self.what,
                shown(&v)
            )));
        }
        Ok(Some(v.is_truthy()?))
    }

    /// A string (or a path, for `PathLike` objects).
    pub fn string(&mut self, key: &'static str) -> PyResult<Option<String>> {
        let Some(v) = self.raw(key)? else {
            return Ok(None);
        };
        if let Ok(s) = v.extract::<String>() {
            return Ok(Some(s));
        }
        if let Ok(p) = v.extract::<PathBuf>() {
            return Ok(Some(p.to_string_lossy().into_owned()));
        }
        Err(user_msg(format!(
            "{}: option `{key}`: expected a string",
            self.what
        )))
    }

    /// The raw object (for options with their own conversion).
    pub fn any(&mut self, key: &'static str) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.raw(key)
    }

    /// Fails on an option that was not read.
    pub fn finish(self) -> PyResult<()> {
        let Some(d) = &self.dict else {
            return Ok(());
        };
        for k in d.keys() {
            let k: String = k.extract()?;
            if !self.read.iter().any(|r| *r == k) {
                // (internal `*_toml` names hidden, and `Filter`'s
                // `calibration`, taken out before, listed: an audit)
                let mut known: Vec<&str> = self
                    .read
                    .iter()
                    .copied()
                    .filter(|r| !r.ends_with("_toml"))
                    .collect();
                if self.what == "method options" && !known.contains(&"calibration") {
                    known.push("calibration");
                }
                known.sort_unstable();
                return Err(user_msg(format!(
                    "{}: unknown option `{k}` (accepted here: {})",
                    self.what,
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                )));
            }
        }
        Ok(())
    }
}

/// Resolves a method: its name, `params` (None, a TOML file path or a
/// dict of the same keys) and the method's options (`limbfuse estimate`'s
/// flags: `window`, `order`, `library`, `kappa`, `rescale_height`,
/// `imm_weights`, `imm_touchdown`).
pub fn method_spec(
    method: &str,
    params: Option<&Bound<'_, PyAny>>,
    options: Option<Bound<'_, PyDict>>,
) -> PyResult<MethodSpec> {
    let o = Options::new("method options", options);
    method_spec_from(method, params, o)
}

/// The options `calibration` (a file path) and `calibration_toml` (a
/// `Calibration`'s text): the calibration's text and label.
fn calibration_option(o: &mut Options<'_>) -> PyResult<Option<(String, String)>> {
    match (o.string("calibration")?, o.string("calibration_toml")?) {
        (Some(path), None) => {
            let text = std::fs::read_to_string(&path)
                .map_err(|e| user_msg(format!("calibration: cannot read {path}: {e}")))?;
            Ok(Some((text, path)))
        }
        (None, Some(text)) => Ok(Some((text, "<Calibration>".to_string()))),
        (None, None) => Ok(None),
        (Some(_), Some(_)) => Err(user_msg(
            "method options: give `calibration` (a file) or `calibration_toml`, not both",
        )),
    }
}

/// Takes the calibration options out of `options` (for `Filter`, whose
/// other options are the method's): the calibration's text and label.
pub fn take_calibration(options: &Bound<'_, PyDict>) -> PyResult<Option<(String, String)>> {
    let picked = PyDict::new(options.py());
    for key in ["calibration", "calibration_toml"] {
        if let Some(v) = options.get_item(key)? {
            picked.set_item(key, v)?;
            options.del_item(key)?;
        }
    }
    let mut o = Options::new("method options", Some(picked));
    calibration_option(&mut o)
}

/// What `estimate` runs: the method, the diagnostic columns, `--backfill`
/// and an IMU calibration (the file's text and its label).
pub struct EstimateRun {
    /// The method.
    pub spec: MethodSpec,
    /// The diagnostic columns written.
    pub diagnostics: DiagnosticColumns,
    /// `backfill=True`.
    pub backfill: bool,
    /// `smooth=True` (`chain`'s RTS smoother, `--smooth`).
    pub smooth: bool,
    /// `calibration=` (a file) or `calibration_toml=` (its text): text, label.
    pub calibration: Option<(String, String)>,
}

/// [`method_spec`] for `estimate`, which also takes the options
/// `diagnostics` (`limbfuse estimate --diagnostics`): `"all"` (the
/// default), `"none"`, or diagnostic names (a comma-separated string or a
/// list of strings, with or without `diag_`); `backfill` (`--backfill`)
/// and `smooth` (`--smooth`), booleans.
pub fn estimate_spec(
    method: &str,
    params: Option<&Bound<'_, PyAny>>,
    options: Option<Bound<'_, PyDict>>,
) -> PyResult<EstimateRun> {
    let mut o = Options::new("method options", options);
    let backfill = o.bool("backfill")?.unwrap_or(false);
    let smooth = o.bool("smooth")?.unwrap_or(false);
    if backfill && smooth {
        return Err(user_msg(
            "method options: `backfill` (knee methods) and `smooth` (`chain`) cannot be used together",
        ));
    }
    let calibration = calibration_option(&mut o)?;
    let diagnostics = match o.any("diagnostics")? {
        None => DiagnosticColumns::All,
        Some(v) => {
            let text = if let Ok(s) = v.extract::<String>() {
                s
            } else if let Ok(names) = v.extract::<Vec<String>>() {
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(",")
                }
            } else {
                return Err(user_msg(
                    "method options: option `diagnostics`: expected \"all\", \"none\" or diagnostic \
                     names (a comma-separated string or a list of strings)",
                ));
            };
            DiagnosticColumns::parse(&text)
                .map_err(|e| user_msg(python_spelling(&chain_message(&e))))?
        }
    };
    Ok(EstimateRun {
        spec: method_spec_from(method, params, o)?,
        diagnostics,
        backfill,
        smooth,
        calibration,
    })
}

fn method_spec_from(
    method: &str,
    params: Option<&Bound<'_, PyAny>>,
    mut o: Options<'_>,
) -> PyResult<MethodSpec> {
    let name = MethodName::parse(method).map_err(|e| user_error(&e))?;
    let flags = MethodFlags {
        window: o.u64("window")?.map(|v| v as usize),
        order: o.u64("order")?.map(|v| v as usize),
        library: o.string("library")?.map(PathBuf::from),
        kappa: o.f64("kappa")?,
        rescale_height: o.f64("rescale_height")?,
        imm_weights: o.string("imm_weights")?,
        imm_touchdown: o.string("imm_touchdown")?,
        imm_config: o.string("imm_config")?,
        imm_extend_library: o.string("imm_extend_library")?,
        leg_length: o.f64("leg_length")?,
        mass: o.f64("mass")?,
    };
    o.finish()?;
    let params = params.filter(|p| !p.is_none());
    let spec = match params {
        None => MethodSpec::from_parts(name, None, &flags),
        Some(p) if p.is_instance_of::<PyDict>() => {
            let text = toml_text(p.downcast::<PyDict>()?)?;
            let label = PathBuf::from("<params dict>");
            MethodSpec::from_parts(name, Some((&text, &label)), &flags)
        }
        // A parameter file's text (e.g. `default_params(...)` edited): a
        // path never holds a line break (an audit: the text was taken for a
        // file name and "not found").
        Some(p) if p.extract::<String>().is_ok_and(|t| t.contains('\n')) => {
            let text: String = p.extract()?;
            let label = PathBuf::from("<params text>");
            MethodSpec::from_parts(name, Some((&text, &label)), &flags)
        }
        Some(p) => {
            let path: PathBuf = p.extract().map_err(|_| {
                user_msg(
                    "params: expected None, a parameter file path, a parameter file's text or a \
                     dict of parameters",
                )
            })?;
            MethodSpec::resolve(name, Some(&path), &flags)
        }
    };
    spec.map_err(|e| user_msg(python_spelling(&chain_message(&e))))
}

/// The method layer's messages name `limbfuse estimate`'s flags
/// (`--window`, `--rescale-height`); here they are keywords (`window`,
/// `rescale_height`: an audit found `estimate(..., window=500)` answered
/// with "--window and --order apply to ..."); a CLI subcommand with a Python
/// function is that function's call.
pub(crate) fn python_spelling(message: &str) -> String {
    const FLAGS: [&str; 16] = [
        "window",
        "order",
        "library",
        "kappa",
        "rescale-height",
        "imm-weights",
        "imm-touchdown",
        "imm-config",
        "imm-extend-library",
        "leg-length",
        "mass",
        "diagnostics",
        "smooth",
        "backfill",
        "calibration",
        "params",
    ];
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(i) = rest.find("--") {
        out.push_str(&rest[..i]);
        let after = &rest[i + 2..];
        let word_end = after
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
            .unwrap_or(after.len());
        let word = &after[..word_end];
        // (a flag starts a word: `my--window.csv` is a file name)
        let starts_word = !out.ends_with(|c: char| c.is_ascii_alphanumeric() || c == '_');
        if starts_word && FLAGS.contains(&word) {
            out.push_str(&word.replace('-', "_"));
        } else {
            out.push_str("--");
            out.push_str(word);
        }
        rest = &after[word_end..];
    }
    out.push_str(rest);
    // The CLI subcommands a message sends the user to that are Python
    // calls here (an audit, session 31: `estimate(t, "imm-bslip")` without
    // a library said "build one with `limbfuse gait-library build`").
    const COMMANDS: [(&str, &str); 1] = [(
        "`limbfuse gait-library build`",
        "`limbfuse.gait_library(path, speeds)`",
    )];
    for (cli, python) in COMMANDS {
        out = out.replace(cli, python);
    }
    out
}

/// A dict of parameters as the text of a TOML parameter file.
pub(crate) fn toml_text(d: &Bound<'_, PyDict>) -> PyResult<String> {
    let table = toml_table(d, "params")?;
    toml::to_string(&table).map_err(|e| user_msg(format!("params: {e}")))
}

fn toml_table(d: &Bound<'_, PyDict>, at: &str) -> PyResult<toml::Table> {
    let mut t = toml::Table::new();
    for (k, v) in d.iter() {
        let key: String = k
            .extract()
            .map_err(|_| user_msg(format!("{at}: every key must be a string")))?;
        let value = toml_value(&v, &format!("{at}[{key:?}]"))?;
        t.insert(key, value);
    }
    Ok(t)
}

fn toml_value(v: &Bound<'_, PyAny>, at: &str) -> PyResult<toml::Value> {
    if is_bool(v) {
        return Ok(toml::Value::Boolean(v.is_truthy()?));
    }
    if v.is_instance_of::<PyInt>() {
        let i: i64 = v
            .extract()
            .map_err(|_| user_msg(format!("{at}: integer out of range")))?;
        return Ok(toml::Value::Integer(i));
    }
    if v.is_instance_of::<PyFloat>() {
        let x: f64 = v.extract()?;
        // `inf` passes as the TOML file's `inf` (the defaults use it for
        // "off", e.g. `accel_max_rate`; an audit: the defaults read back as a
        // dict were refused); the parameter file's checks judge it.
        if x.is_nan() {
            return Err(user_msg(format!("{at}: expected a number, found nan")));
        }
        return Ok(toml::Value::Float(x));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract()?));
    }
    if let Ok(d) = v.downcast::<PyDict>() {
        return Ok(toml::Value::Table(toml_table(d, at)?));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, x) in v.try_iter()?.enumerate() {
            out.push(toml_value(&x?, &format!("{at}[{i}]"))?);
        }
        return Ok(toml::Value::Array(out));
    }
    // numpy scalars and other numbers: an integer (`__index__`, numpy's
    // int64) stays an integer (an audit: `{"window": np.int64(500)}` was
    // written `500.0` and refused for a float)
    if let Ok(i) = v.extract::<i64>() {
        return Ok(toml::Value::Integer(i));
    }
    if let Ok(x) = v.extract::<f64>() {
        return toml_value(&PyFloat::new(v.py(), x).into_any(), at);
    }
    Err(user_msg(format!(
        "{at}: expected a number, string, bool, list or dict, found {}",
        v.get_type().name()?
    )))
}

#[cfg(test)]
mod tests {
    use super::python_spelling;

    #[test]
    fn method_flags_become_keywords_and_nothing_else_changes() {
        assert_eq!(
            python_spelling(
                "--window and --order apply to methods knee-selfalign and knee-gyro-axis only"
            ),
            "window and order apply to methods knee-selfalign and knee-gyro-axis only"
        );
        assert_eq!(
            python_spelling("--rescale-height 0: expected a positive height; see --help"),
            "rescale_height 0: expected a positive height; see --help"
        );
        assert_eq!(
            python_spelling("(file keys or --window/--order)"),
            "(file keys or window/order)"
        );
        assert_eq!(python_spelling("a -- b --"), "a -- b --");
        assert_eq!(
            python_spelling(
                "method `imm-bslip` needs --library LIB.json (build one with `limbfuse gait-library build`)"
            ),
            "method `imm-bslip` needs library LIB.json (build one with `limbfuse.gait_library(path, speeds)`)"
        );
        assert_eq!(
            python_spelling("my--window.csv: --window"),
            "my--window.csv: window"
        );
    }
}
