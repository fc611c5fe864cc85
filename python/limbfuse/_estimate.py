"""`Estimate`, `estimate` and `evaluate`."""

from __future__ import annotations

import json
import operator
import os
import warnings
from types import MappingProxyType
from typing import (
    TYPE_CHECKING,
    Any,
    Dict,
    List,
    Literal,
    Mapping,
    Optional,
    Sequence,
    SupportsIndex,
    Tuple,
    Union,
    overload,
)

import numpy as np

from . import _native
from ._arrays import (
    SetOnce,
    as_column,
    as_time,
    filled,
    fingerprint,
    from_native,
    frozen,
    phase_array,
    phase_cells,
    same_samples,
    split_header,
)
from ._calibration import calibration_options
from ._lazy import LazyModule
from ._trial import PathLike, Trial

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
else:  # (pandas is imported on first use; `_lazy`)
    pd = LazyModule("pandas")

PHASE = "phase"


class LimbfuseWarning(UserWarning):
    """A warning the CLI prints on stderr (e.g. an estimator restarted)."""


class Estimate(SetOnce):
    """The output of one method over one trial (SPEC section 3).

    Attributes:
        t: time (s), the trial's.
        channels: read-only mapping of column name (``trunk`` ... ``ankle``
            in rad, ``speed``, ``com_x`` ... ``com_vz``, ``diag_NAME``) to a
            float64 array, masked where the method gave no value; ``t`` and
            the arrays are read-only views.
        phase: estimated gait phase (object array of ``"SS1"``, ``"DS"``,
            ``"SS2"`` or None) or None.
        header: the estimate file's ``key: value`` header lines.
        method: the method name; ``params``: its parameters as written in
            the header.
        columns: the file's column names in order (``t`` first).
        summary: for a knee-axis method (``knee-selfalign``,
            ``knee-gyro-axis``) run by ``estimate``, the line ``limbfuse
            estimate`` prints: when the axis was identified, the sign
            confidence and whether the sign is committed (if not, the knee
            may come out negated: weak evidence), how often the
            accelerometer angle corrected the drift; None otherwise (and
            for an estimate read from a file).

    Build one from arrays, ``Estimate(t, {"knee": k, ...}, method="mine")``
    (``phase`` or a ``"phase"`` channel: the gait-phase labels; ``header``:
    the header lines, default ``["method: METHOD"]``), e.g. to score or
    report another tool's output. The attributes cannot be replaced.
    """

    __slots__ = ("t", "channels", "phase", "header", "method", "params", "columns", "summary", "_trial_fingerprint")
    t: np.ndarray
    channels: Mapping[str, np.ndarray]
    phase: Optional[np.ndarray]
    header: List[str]
    method: str
    params: Dict[str, str]
    columns: List[str]
    summary: Optional[str]
    _trial_fingerprint: Optional[Dict[str, Any]]

    def __init__(
        self,
        t: Any,
        channels: Mapping[str, Any],
        method: str = "unknown",
        phase: Any = None,
        header: Optional[Sequence[str]] = None,
    ) -> None:
        t = as_time(t)
        cols = {name: as_column(name, v, t.shape[0]) for name, v in channels.items() if name != PHASE}
        if PHASE in channels and phase is None:
            phase = channels[PHASE]
        self._set(
            t,
            cols,
            None if phase is None else phase_array(phase_cells(PHASE, phase, t.shape[0])),
            list(header) if header is not None else [f"method: {method}"],
            None,
        )
        self._check()

    def _set(
        self,
        t: np.ndarray,
        cols: Mapping[str, np.ndarray],
        phase: Optional[np.ndarray],
        header: Sequence[str],
        order: Optional[Sequence[str]],
        summary: Optional[str] = None,
    ) -> None:
        # (set by `estimate`: which in-memory trial it was made from)
        self._trial_fingerprint = None
        self.t = frozen(t)
        self.channels = MappingProxyType({n: frozen(a) for n, a in cols.items()})
        self.phase = phase
        self.header = list(header)
        entries, params = split_header(self.header)
        self.method = entries.get("method", "unknown")
        self.params = params
        names = list(cols)
        if order is None:
            order = ["t"] + names[:]
            if phase is not None:
                order.append(PHASE)
        self.columns = list(order)
        self.summary = summary

    def _check(self) -> None:
        # The extension checks names and lengths when it reads the columns.
        _native.check_estimate(self._native())

    def _native(self) -> tuple:
        names = list(self.channels)
        return (
            self.header,
            self.t,
            names,
            [filled(self.channels[n]) for n in names],
            None if self.phase is None else list(self.phase),
        )

    @classmethod
    def _from_native(cls, tup: tuple) -> "Estimate":
        header, order, t, names, arrays, phase, resets, has_nan, summary = tup
        if has_nan is None:
            cols = {n: from_native(a) for n, a in zip(names, arrays)}
        else:
            cols = {n: from_native(a) if nan else a for n, a, nan in zip(names, arrays, has_nan)}
        e = cls.__new__(cls)
        e._set(t, cols, phase_array(phase), header, order, summary)
        if resets:
            warnings.warn(resets, LimbfuseWarning, stacklevel=3)
        return e

    def to_pandas(self) -> "pd.DataFrame":
        """The estimate as a DataFrame in the file's column order (NaN or
        None = not estimated); ``attrs["header"]`` holds the header lines."""
        import pandas as pd

        data: Dict[str, Any] = {}
        for name in self.columns:
            if name == "t":
                data[name] = self.t
            elif name == PHASE:
                data[name] = self.phase
            else:
                data[name] = filled(self.channels[name])
        df = pd.DataFrame(data)
        df.attrs["header"] = list(self.header)
        return df

    def strides(
        self,
        trial: Optional[Trial] = None,
        allow_trial_mismatch: bool = False,
        window: Union[None, str, Tuple[Optional[float], Optional[float]]] = None,
    ) -> "pd.DataFrame":
        """One row per stride of a ``gait-events`` or ``lowback-speed``
        estimate, as ``limbfuse evaluate TRIAL EST --strides FILE`` writes
        them (docs/GAIT_EVENTS.md "Stride table"): the strides the method
        writes as sparse ``diag_*`` cells, put back together.

        Columns: ``foot`` (``left``, ``right``; ``unknown`` for
        ``lowback-speed``, which does not tell the feet apart), ``ic_s``
        (start: the back-dated initial contact), ``fc_s`` (the foot's final
        contact inside the stride), ``end_s`` (the next initial contact of
        that foot), ``decided_s`` (when the method decided the stride),
        ``stride_time_s``, ``stance_time_s`` (``fc_s - ic_s``),
        ``swing_time_s`` (``end_s - fc_s``; both ``gait-events`` only),
        ``stride_length_m``, ``speed_m_s``, ``acc_clipped_s``
        (``gait-events``: how long the stride's accelerometer sat at its
        full scale; beyond 0.04 s the swing clipped and the stride is
        short); ``turn_rate_rad_s`` (mean heading rate over the stride:
        the trunk's for ``lowback-speed``, the foot's for ``gait-events``),
        ``speed_withheld`` (``turn`` / ``after_turn``: why the stride has no
        speed or length; a stride of either method that turns faster than
        15 deg/s has none); ``lowback-speed`` only: ``step_length_1_m``,
        ``step_length_2_m``. With ``trial`` (its references), what ``evaluate`` pairs with
        each stride: ``ic_ref_s`` (the reference initial contact paired with
        ``ic_s``), ``fc_ref_s`` (the reference final contact paired with
        ``fc_s``), ``stride_time_ref_s``, ``stance_time_ref_s`` (``fc_ref_s -
        ic_ref_s``), ``swing_time_ref_s`` (the reference contact paired with
        ``end_s`` minus ``fc_ref_s``), ``speed_ref_m_s`` (mean ``speed_ref``
        over the stride), ``stride_length_ref_m``; ``evaluate``'s per-stride
        ``speed_mae_mps`` is the mean of ``|speed_m_s - speed_ref_m_s|`` over
        the rows with both, its ``stance_time_mae_ms`` / ``swing_time_mae_ms``
        (and ``_bias_ms``) those of the stance and swing time errors over the
        ``n_stance_swing`` rows with both reference times. NaN: not known.
        Sorted by ``ic_s``.

        ``window`` (``"10:40"`` or ``(10, 40)``, s; with ``trial`` only):
        the references outside it count as unknown, as ``evaluate(trial,
        estimate, window=...)`` scores them (``limbfuse evaluate --window
        A:B --strides FILE``); every stride is listed.

        Raises ``LimbfuseError`` for an estimate without strides (another
        method, or estimated with ``diagnostics`` that leave out the stride
        columns) and, unless ``allow_trial_mismatch``, for a trial the
        estimate was not made from.
        """
        import pandas as pd

        if trial is not None and not isinstance(trial, Trial):
            raise TypeError("Estimate.strides: trial must be a limbfuse.Trial or None")
        allow_trial_mismatch = flag("allow_trial_mismatch", allow_trial_mismatch)
        if trial is not None:
            mismatch = _trial_mismatch(trial, self)
            if mismatch is not None and not allow_trial_mismatch:
                raise _native.LimbfuseError(
                    f"{mismatch}: refusing to pair the strides with another trial's references "
                    "(allow_trial_mismatch=True pairs them anyway)"
                )
        if window is not None and trial is None:
            raise ValueError(
                "Estimate.strides: window selects the references that are scored; give the trial too"
            )
        foot, withheld, numbers = _native.strides(
            self._native(), None if trial is None else trial._native(), True, _window_text(window)
        )
        # (text columns take pandas' default string dtype, as `read_csv` of the CLI's file)
        data: Dict[str, Any] = {"foot": pd.Series(foot)}
        for name, values in numbers:
            if name == "ic_ref_s":
                data["speed_withheld"] = pd.Series([w if w else np.nan for w in withheld])
            data[name] = np.asarray(values, dtype=np.float64)
        return pd.DataFrame(data)

    def write(self, path: PathLike) -> None:
        """Writes the estimate file (CSV); for an estimate of a trial read
        from a file, the same bytes as ``limbfuse estimate -o`` but its
        ``# command:`` line (which says how the CLI was called). An Arrow
        name (``.arrow``, ``.feather``, ``.ipc``) is refused: the CLI writes
        those (docs/ARROW.md), or ``to_pandas().to_feather(path)``."""
        if os.path.splitext(os.fsdecode(path))[1].lower() in (".arrow", ".feather", ".ipc"):
            raise _native.LimbfuseError(
                f"{os.fsdecode(path)}: Estimate.write writes CSV files; for an Arrow file use "
                "`limbfuse estimate ... -o NAME.arrow` or `estimate.to_pandas().to_feather(path)`"
            )
        _native.write_estimate(os.fsdecode(path), self._native())

    def __len__(self) -> int:
        return int(self.t.shape[0])

    def __reduce__(self) -> tuple:
        # pickle, copy.deepcopy, multiprocessing (as `Trial`)
        state = (self.t, dict(self.channels), self.phase, self.header, self.columns, self._trial_fingerprint)
        return (_estimate_from_state, state)

    def __repr__(self) -> str:
        return f"<Estimate {self.method}: {len(self)} samples, columns {', '.join(self.columns[1:8])}{'...' if len(self.columns) > 8 else ''}>"


def _estimate_from_state(t, channels, phase, header, columns, made_from) -> Estimate:
    e = Estimate(t, channels, phase=phase, header=header)
    object.__setattr__(e, "columns", list(columns))  # (the file's order, kept)
    e._trial_fingerprint = made_from
    return e


def estimate(
    trial: Trial,
    method: str,
    params: Union[None, PathLike, Mapping[str, Any]] = None,
    **options: Any,
) -> Estimate:
    """Runs `method` over `trial` in memory (the GIL is released).

    Args:
        trial: the trial.
        method: a method name (``limbfuse.METHODS``).
        params: None (defaults), a TOML parameter file
            (``limbfuse params --method NAME``), its text (a string with a
            line break, e.g. ``default_params(NAME)`` edited) or a dict of
            the same keys.
        **options: the method's ``limbfuse estimate`` flags: ``window``,
            ``order`` (knee-selfalign, knee-gyro-axis), ``library``, ``kappa``,
            ``rescale_height``, ``imm_weights``, ``imm_touchdown``, ``imm_config``,
            ``imm_extend_library``, ``leg_length``, ``mass`` (imm-bslip); and ``diagnostics``
            (``--diagnostics``): ``"all"`` (default), ``"none"``, or
            diagnostic names (a comma-separated string or a list, e.g.
            ``["sd_thigh", "sd_shank"]``: the ``diag_`` columns of an
            estimate with ``"all"``; a name the method lacks is refused with
            the list of its diagnostics). Fewer columns make a smaller,
            faster call.
            ``backfill=True`` (``--backfill``; knee-selfalign,
            knee-gyro-axis): the knee angle before the first identified
            window, filled offline (docs/KNEE_SELFALIGN.md "Backfill").
            ``smooth=True`` (``--smooth``; chain): the RTS smoother, each
            estimate final once later samples were seen (docs/CHAIN.md).
            ``calibration`` (``--calibration``): a calibration file or a
            ``Calibration`` from ``calibrate``, applied to every IMU
            reading before the method sees it (docs/CALIBRATION.md).

    With ``imm_config="continuous"`` a trial walking outside the gait
    library's speeds is estimated twice, as ``limbfuse estimate`` does: the
    missing gaits are searched for the trial's body and added to the family
    (``imm_extend_library="off"`` keeps the library as it is); a
    ``LimbfuseWarning`` says which speeds were added, with the CLI's text
    (docs/GAIT_IMM.md). ``Filter`` steps once through the samples and never
    extends.

    Raises:
        LimbfuseError: unknown method, bad parameter, a channel the method
            needs is missing, or the estimator failed (the message names it).
    """
    if not isinstance(trial, Trial):
        raise TypeError(f"estimate: expected a limbfuse.Trial, found {type(trial).__name__}")
    p = os.fsdecode(params) if isinstance(params, (str, bytes, os.PathLike)) else params
    options = calibration_options(options)
    e = Estimate._from_native(_native.estimate(trial._native(), method, p, options or None))
    e._trial_fingerprint = fingerprint(trial.t, trial.channels)
    return e


def read_estimate(path: PathLike) -> Estimate:
    """Reads an estimate file."""
    return Estimate._from_native(_native.read_estimate(os.fsdecode(path)))


def _window_text(window: Union[None, str, Tuple[Optional[float], Optional[float]]]) -> Optional[str]:
    if window is None or isinstance(window, str):
        return window
    try:
        start, end = window
    except (TypeError, ValueError):
        raise _native.LimbfuseError(
            f"window: expected \"START:END\" or (start, end) in seconds, found {window!r}"
        ) from None

    def fmt(x: Any) -> str:
        if x is None:
            return ""
        if isinstance(x, (bool, str, bytes)) or not isinstance(x, (int, float, np.integer, np.floating)):
            raise TypeError(f"window: expected numbers (s) or None for its ends, found {x!r}")
        return repr(float(x))

    return f"{fmt(start)}:{fmt(end)}"


def flag(name: str, value: Any) -> bool:
    """A True/False option, checked (a string such as "no" is truthy)."""
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name}: expected True or False, found {value!r}")
    return bool(value)


def count(name: str, value: Any, least: int, most: Optional[int]) -> int:
    """An integer option in [least, most] (``most`` None: no upper bound),
    checked and named."""
    if isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name}: expected an integer, found {value!r}")
    try:
        value = operator.index(value)  # (int, numpy integers: not 1.5 or "3")
    except TypeError:
        raise TypeError(f"{name}: expected an integer, found {value!r}") from None
    if value < least or (most is not None and value > most):
        upto = f"from {least} to {most}" if most is not None else f"of at least {least}"
        raise _native.LimbfuseError(f"{name}: expected an integer {upto}, found {value}")
    return int(value)


def evaluate(
    trial: Trial,
    estimate: Estimate,
    window: Union[None, str, Tuple[Optional[float], Optional[float]]] = None,
    offset_free: bool = False,
    max_lag: SupportsIndex = 0,
    allow_trial_mismatch: bool = False,
) -> Dict[str, Any]:
    """Errors of `estimate` against the trial's reference: the same object
    (and numbers) as ``limbfuse evaluate --json`` (angles in degrees).

    An estimate of gait events or walking speed (``gait-events``,
    ``lowback-speed``) gets the event evaluation (timing, contacts, stride
    speed; docs/GAIT_EVENTS.md), a paper-003 gait trial the phase / CoM /
    speed evaluation, as the CLI chooses them.

    Args:
        window: ``"10:40"`` or ``(10, 40)`` (s); either end may be open.
            For an event evaluation, only the rows inside it are scored.
        offset_free: remove each channel's mean error before the RMSE
            (angles only: refused for an event or gait evaluation);
            ``max_abs_err_deg`` and ``mean_err_deg`` stay as measured,
            before the mean is removed.
        max_lag: synchronise each channel within +-max_lag samples (angles
            only, likewise).
        allow_trial_mismatch: evaluate an estimate recording another trial.

    Angle references that look like degrees (a quarter of a channel's
    values beyond pi) give a ``LimbfuseWarning`` and a ``warnings`` entry,
    as the CLI's.
    """
    if not isinstance(trial, Trial) or not isinstance(estimate, Estimate):
        raise TypeError("evaluate: expected a limbfuse.Trial and a limbfuse.Estimate")
    # (a wrong type is a TypeError, as every option's; an audit: 1.5 raised LimbfuseError)
    max_lag = count("max_lag", max_lag, 0, None)
    # (the extension bounds it by half the trial; beyond 2**32 no trial is that long)
    max_lag = min(max_lag, 2**32)
    allow_trial_mismatch = flag("allow_trial_mismatch", allow_trial_mismatch)
    mismatch = _trial_mismatch(trial, estimate)
    if mismatch is not None:
        if not allow_trial_mismatch:
            raise _native.LimbfuseError(
                f"{mismatch}: refusing to evaluate an estimate made from another trial "
                "(allow_trial_mismatch=True evaluates it anyway)"
            )
        # (the CLI's warning; an audit: Python said nothing)
        warnings.warn(f"{mismatch} (evaluated anyway, as asked)", LimbfuseWarning, stacklevel=2)
    text = _native.evaluate(
        trial._native(),
        estimate._native(),
        _window_text(window),
        flag("offset_free", offset_free),
        max_lag,
        # (checked above by the samples when this session made the estimate;
        # the extension's check compares file hashes)
        allow_trial_mismatch or estimate._trial_fingerprint is not None,
    )
    result = json.loads(text)
    # (references that look like degrees: the CLI's stderr warning)
    for w in result.get("warnings", []):
        warnings.warn(w, LimbfuseWarning, stacklevel=2)
    return result


def _trial_mismatch(trial: Trial, estimate: Estimate) -> Optional[str]:
    """Why `estimate` was not made from `trial`, if it was not: an estimate
    made in memory by ``estimate`` against another in-memory trial (an
    audit: scored silently), or, as ``limbfuse evaluate`` checks, one whose
    header records another trial file's hash."""
    if len(trial) != len(estimate):
        return None  # (the extension says which lengths differ)
    # The samples first when this session made the estimate (a trial read
    # from its CSV and from its Arrow copy are one trial; an audit: their
    # file hashes differ), else the file hash the estimate records.
    entries = split_header(estimate.header)[0]
    made_from = estimate._trial_fingerprint
    if made_from is not None:
        if same_samples(made_from, fingerprint(trial.t, trial.channels)):
            return None
        if "trial" in entries and trial.source is not None:
            return (
                f"the estimate was made from `{entries['trial']}` but the trial is "
                f"`{trial.source[0]}` (their samples differ)"
            )
        return "the estimate was made from another trial than the one given (their samples differ)"
    recorded = entries.get("trial_hash")
    if trial.source is None or recorded in (None, "streamed") or recorded == trial.source[1]:
        return None
    made = entries.get("trial", "another trial")
    return f"the estimate was made from `{made}` ({recorded}) but the trial is `{trial.source[0]}` ({trial.source[1]})"


@overload
def methods() -> List[Tuple[str, str]]: ...
@overload
def methods(details: Literal[False]) -> List[Tuple[str, str]]: ...
@overload
def methods(details: Literal[True]) -> List[Dict[str, str]]: ...


def methods(details: bool = False) -> Union[List[Tuple[str, str]], List[Dict[str, str]]]:
    """Every method: (name, one-line summary), as ``limbfuse methods`` lists
    them; with ``details=True`` a dict per method with ``name``,
    ``summary``, ``reads`` (the channels it reads) and ``settings`` (what
    its parameter file or options set), the lines of ``limbfuse methods``."""
    if not isinstance(details, bool):
        raise TypeError(f"details: expected True or False, found {details!r}")
    if not details:
        return list(_native.methods())
    return [
        {"name": n, "summary": s, "reads": r, "settings": st} for n, s, r, st in _native.method_details()
    ]


def default_params(method: str) -> str:
    """A method's default parameter file, commented (``limbfuse params``)."""
    return _native.default_params(method)


def inspect(path: Union[PathLike, Trial]) -> Dict[str, Any]:
    """What a trial file (or an in-memory ``Trial``, written to a temporary
    Arrow file first) holds and which methods run on it (``limbfuse
    inspect``), read once without estimating anything.

    Returns a dict: ``rows``; ``span`` (first, last ``t``) or None;
    ``median_step`` (s, of the first 64 samples) and ``stated_hz`` (the
    file's ``# sample_rate_hz:``), each or None; ``gaps`` (steps over 1.5
    median steps) and ``longest_step`` (start ``t``, length) or None;
    ``inputs``: {group: rows missing} (``"thigh gyr"``, ``"knee_enc"``,
    ...); ``warnings``: the unit checks of ``estimate`` (a time column not
    in seconds, accelerometers in g, gyroscopes in deg/s;
    docs/ROBUST_INPUT.md); ``methods``: {name: (kind, why)} with kind
    ``"runs"``, ``"runs after align"`` (it reads aligned frames, the file
    declares raw ones; why: ``align`` first, or why ``align`` cannot align
    the trial, as ``limbfuse inspect`` says on the method's line),
    ``"needs a setting"`` (a model, a gait library),
    ``"missing columns"`` or ``"no usable data"`` (the columns are there,
    the data rule it out: an input empty on every row a knee-axis method
    needs, a trial shorter than its window), and why: the message
    ``estimate`` would give;
    ``metadata_settings``: one line per method that reads body or sensor
    geometry from the metadata (``lowback-speed``'s pendulum,
    ``knee-kinematic``'s lever arm, ``imm-bslip``'s body, ``chain``'s
    geometry): the value its defaults take on this trial and its source;
    ``thigh_spread_deg``: the angular deviation of the thigh accelerometer's
    direction (deg; None without a thigh accelerometer), and
    ``data_notes``: what it says about the methods that run
    (``knee-kinematic`` models a fixed thigh and the thigh moves; a walking
    method on a thigh that does not move, where it finds no gait);
    ``align``: whether ``limbfuse align`` can align the trial, as
    ``limbfuse inspect`` says it: {``"needed"``: some method runs only after
    it (``"runs after align"``), ``"possible"``: True (it aligns the
    trial), False (it cannot: ``"reason"``, its error) or None (not checked:
    not needed, or over 200 000 rows), ``"reason"``: str or None}.

    Raises:
        LimbfuseError: the file cannot be read (the message names the file
            and line).
    """
    if isinstance(path, Trial):
        import tempfile

        with tempfile.TemporaryDirectory() as tmp:
            file = os.path.join(tmp, "trial.arrow")
            path.write(file)
            return inspect(file)
    (rows, span, step, stated, gaps, longest, inputs, warnings_, methods_, read, spread, (notes, align)) = (
        _native.inspect(os.fsdecode(path))
    )
    return {
        "rows": rows,
        "span": span,
        "median_step": step,
        "stated_hz": stated,
        "gaps": gaps,
        "longest_step": longest,
        "inputs": dict(inputs),
        "warnings": list(warnings_),
        "methods": {name: (kind, _after_align(kind, why, align)) for name, kind, why in methods_},
        "metadata_settings": list(read),
        "thigh_spread_deg": spread,
        "data_notes": list(notes),
        "align": {"needed": align[0], "possible": align[1], "reason": align[2]},
    }


def _after_align(kind: str, why: str, align: Tuple[Any, Any, Any]) -> str:
    """The reason of a method that runs after ``align`` (empty from the
    extension): whether ``align`` can (an audit, session 31: a trunk-only
    raw trial said ``("runs after align", "")`` while ``align`` refuses it;
    the CLI says so on that line)."""
    if kind != "runs after align" or why:
        return why
    if align[1] is False:
        return f"reads aligned frames, but `limbfuse.align` cannot align this trial: {align[2]}"
    return "reads aligned frames and the trial declares raw ones: `limbfuse.align(trial)` first"
