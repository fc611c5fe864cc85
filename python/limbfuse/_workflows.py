"""`simulate`, `align`, `calibrate`, `gait_library`: the CLI's workflows as
functions."""

from __future__ import annotations

import os
import re
import tempfile
import warnings
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, SupportsFloat, SupportsIndex, Tuple, Union

from . import _native
from ._calibration import Calibration
from ._estimate import Estimate, LimbfuseWarning, _window_text, count, flag
from ._trial import PathLike, Trial, read_trial


def simulate(kind: str = "walking", **options: Any) -> Trial:
    """Simulates a trial in memory, as ``limbfuse simulate KIND`` does.

    kinds and options (defaults are the CLI's; each option is the CLI flag
    with ``_`` for ``-``, and ``noise=False`` for ``--no-noise``):
        walking: speed, duration, imu_rate, seed, mounting ("aligned" or
            "random"), noise, out_of_plane, variability, misalignment,
            leg ("right" or "left"), turn_every (s between turn starts;
            with turn_deg, default 180, and turn_s, default 2.5: step turns,
            the leg turning in its swings, docs/SIMULATOR.md),
            gait_reference (``--gait-reference``: the feet's contact and
            the per-stride speed as ``contact_*_ref`` / ``speed_ref``, for
            ``gait-events`` and ``lowback-speed``).
        knee: speed, duration, imu_rate, seed, noise, out_of_plane,
            ap_offset_sd_cm, remount_at (s; with remount_deg, default 50)
            (paper 002 scenario: random IMU orientations and positions).
        knee-fes: subject ("P1-L" ... "P3-R"), duration, rate, seed, noise,
            mounting, gyro_drift (deg/s), activation_dynamics, cycles (leg
            extensions, 6 s each after 2 s of rest, default 5: a longer
            trial warns that the leg rests after them), calibration
            (a path: also write there the calibration recording of the same
            sensors, quiet standing + 4 hip rotations, for ``align(...,
            procedure="static-rotation", calibration=...)``) (paper 004).
        fixed-hip: duration, rate, seed, noise, gyro_drift (deg/s),
            activation_t_a (s) (paper 004).
        bslip: speed (m/s, default 0.7), library (a gait-library file to
            take the gait from; else it is searched now for mass, default
            80 kg, and leg_length, default 1.0 m), duration, rate, seed,
            position_only (paper 003).
        calibration: seed, imu_rate, noise, poses, hold, transition,
            lever_arm, wobble_pose (numbered from 1) (the sensors of
            ``simulate("walking", seed=N)`` held still in poses, for
            ``calibrate``).
    """
    if isinstance(options.get("calibration"), os.PathLike):
        options["calibration"] = os.fspath(options["calibration"])
    return Trial._from_native(_native.simulate(kind, options or None))


_ALIGN_OPTIONS = {"procedure", "hinge", "partial", "mean_angle", "calibration", "imu_calibration"}


def align(trial: Trial, **options: Any) -> Trial:
    """Sensor-to-segment alignment (``limbfuse align``): the aligned trial,
    its metadata annotated with the rotations (and the detected leg).

    options:
        procedure: "walking" (default: from walking data, docs/ALIGNMENT.md)
            or "static-rotation" (paper 004 sec 3.3: quiet standing + hip
            flexion/extension rotations).
        hinge (bool), partial (bool), mean_angle ({segment: degrees}, the
            walking mean angle when the trial has no quiet standing): the
            walking procedure's (``--hinge``, ``--partial``, ``--mean-angle``).
        calibration: static-rotation only, the recording of quiet standing
            and rotations of the same sensors (a ``Trial`` or its file;
            default: the calibration segment at the start of `trial`).
        imu_calibration: an IMU calibration (a ``Calibration`` from
            ``calibrate`` or its file) applied to the raw channels first
            (``--imu-calibration``).

    The CLI's warnings (readings left out of the alignment, a detected leg
    replacing the declared one) are ``LimbfuseWarning``s.
    """
    if not isinstance(trial, Trial):
        raise TypeError(f"align: expected a limbfuse.Trial, found {type(trial).__name__}")
    options = {k: v for k, v in options.items() if v is not None}  # None: the default
    unknown = sorted(set(options) - _ALIGN_OPTIONS)
    if unknown:
        raise _native.LimbfuseError(
            f"align: unknown option `{unknown[0]}` (accepted: {', '.join(sorted(_ALIGN_OPTIONS))})"
        )
    if "calibration" in options:
        rec = options.pop("calibration")
        if isinstance(rec, (str, os.PathLike)):
            rec = read_trial(rec)
        if not isinstance(rec, Trial):
            raise TypeError(
                "align: `calibration` is the static-rotation recording (a limbfuse.Trial or its file), found "
                f"{type(rec).__name__}; an IMU calibration is `imu_calibration=`"
            )
        options["calibration_trial"] = rec._native()
    cal = options.get("imu_calibration")
    if isinstance(cal, Calibration):
        options["imu_calibration_toml"] = options.pop("imu_calibration").toml
    elif isinstance(cal, (str, os.PathLike)):
        options["imu_calibration"] = os.fspath(cal)
    elif cal is not None:
        raise TypeError(
            f"align: `imu_calibration`: expected a Calibration (limbfuse.calibrate) or its file, found {type(cal).__name__}"
        )
    tup, said = _native.align(trial._native(), options or None)
    for line in said:
        warnings.warn(line, LimbfuseWarning, stacklevel=2)
    return Trial._from_native(tup)


def calibrate(poses: Trial, **options: Any) -> Calibration:
    """Calibrates every IMU of a pose recording (``limbfuse calibrate``:
    the sensors held still in a dozen orientations, e.g.
    ``simulate("calibration")``).

    options: model ("full", default; "scale"; "bias"), gravity (m/s^2;
    default the recording's ``# g:``), acc_std_max, gyro_std_max, min_pose
    (the CLI's flags).

    Raises:
        LimbfuseError: too few or too similar poses, a moving "pose", bad
            options (the message names the sensor and the problem).
    """
    if not isinstance(poses, Trial):
        raise TypeError(f"calibrate: expected a limbfuse.Trial, found {type(poses).__name__}")
    toml, sensors = _native.calibrate(poses._native(), options or None)
    return Calibration(toml, [dict(s) for s in sensors])


def gait_library(
    path: PathLike,
    speeds: Iterable[SupportsFloat],
    mass: SupportsFloat = 80.0,
    leg_length: SupportsFloat = 1.0,
) -> List[Dict[str, float]]:
    """Builds a B-SLIP gait library (``limbfuse gait-library build``) for
    `speeds` (m/s), writes it to `path` (for ``estimate(..., "imm-bslip",
    library=path)``) and returns one summary per gait."""
    if isinstance(speeds, (str, bytes)):
        raise TypeError(f"speeds: expected a sequence of speeds in m/s, found the string {speeds!r}")
    return list(
        _native.gait_library(
            os.fsdecode(path), _numbers("speeds", speeds), _number("mass", mass), _number("leg_length", leg_length)
        )
    )


def repair_time(path: PathLike, output: PathLike, out_of_order: str = "drop") -> Dict[str, Any]:
    """Writes to `output` (CSV) a copy of the trial file `path` whose time
    increases strictly, as ``limbfuse repair-time`` does (docs/ROBUST_INPUT.md
    "A time column that does not increase"): exact duplicate rows and rows
    repeating the time of the row before are dropped; rows whose time stamp
    goes back are dropped (``out_of_order="drop"``: one of the longest runs
    of rows in file order whose time increases is kept) or sorted into time
    order (``"sort"``). The cells are copied as written.

    Returns ``rows_read``, ``rows_kept``, ``moved`` (rows sorted into
    place), ``sorted_onto_a_taken_time`` (sorted rows that landed on another
    row's time: wrong stamps), ``largest_step_back_s``, ``median_step_s`` (of
    the forward steps) and ``dropped``: one
    dict per dropped row with its ``line``, ``t``, ``reason``
    (``"duplicate"``, ``"same_time_other_values"`` or ``"out_of_order"``)
    and ``kept_line`` (the row it repeats, or None)."""
    if not isinstance(out_of_order, str):
        raise TypeError(f"out_of_order: expected \"drop\" or \"sort\", found {out_of_order!r}")
    return dict(_native.repair_time(os.fsdecode(path), os.fsdecode(output), out_of_order))


def resample(trial: Trial, rate_hz: float, anti_alias: str = "sinc") -> Trial:
    """The trial on a uniform time base at ``rate_hz`` (``limbfuse resample``;
    e.g. 50 Hz, the rate of paper 001): IMU channels low-passed before they
    are downsampled (``anti_alias``: ``"sinc"``, a windowed sinc, default;
    ``"boxcar"``; ``"none"``) and interpolated, the other channels
    interpolated linearly, orientations by slerp, the gait phase held.
    Readings out of the sensors' range are left out as ``estimate`` leaves
    them out, and clipped gyroscope cells carried at the rail; both are said
    in a ``LimbfuseWarning``, with the CLI's words. The result equals the
    CLI's output file for the same trial, value for value."""
    if not isinstance(trial, Trial):
        raise TypeError(f"resample: expected a limbfuse.Trial, found {type(trial).__name__}")
    rate = _number("resample: rate_hz", rate_hz)
    if not isinstance(anti_alias, str):
        raise TypeError(f'resample: anti_alias: expected "sinc", "boxcar" or "none", found {anti_alias!r}')
    tup, said = _native.resample(trial._native(), rate, anti_alias)
    for line in said:
        warnings.warn(line, LimbfuseWarning, stacklevel=2)
    return Trial._from_native(tup)


def mirror(trial: Trial, remount_seed: Optional[int] = None) -> Trial:
    """The trial as the mirror-image leg's sensors would read it
    (``limbfuse mirror``; docs/ALIGNMENT.md, "Both legs"): accelerometers
    (x, y, -z), gyroscopes (-x, -y, z), orientations and the simulator's
    sensor truth mirrored, ``# leg:`` set to the other leg. With
    ``remount_seed`` every sensor is also re-mounted at a random
    orientation drawn from that seed (``--remount-seed``): a test of
    alignment on data it has not seen. Metadata lines that cannot be
    mirrored are left out with a ``LimbfuseWarning``."""
    if not isinstance(trial, Trial):
        raise TypeError(f"mirror: expected a limbfuse.Trial, found {type(trial).__name__}")
    if remount_seed is not None and (
        isinstance(remount_seed, bool) or not isinstance(remount_seed, int) or remount_seed < 0
    ):
        raise TypeError(f"mirror: remount_seed: expected a non-negative integer or None, found {remount_seed!r}")
    if remount_seed is not None and remount_seed > 2**64 - 1:
        raise _native.LimbfuseError(f"mirror: remount_seed: expected at most 2^64 - 1 (a 64-bit seed), found {remount_seed}")
    tup, said = _native.mirror(trial._native(), remount_seed)
    for line in said:
        warnings.warn(line, LimbfuseWarning, stacklevel=2)
    return Trial._from_native(tup)


def import_recording(
    path: PathLike, format: str, leg: Optional[str] = None, calibration: Union[Calibration, PathLike, None] = None
) -> Trial:
    """A real recording converted into a trial (``limbfuse import``;
    docs/IMPORTERS.md): ``format="gaittoolbox"`` reads a gait-tech
    gaittoolbox sample folder (Xsens ``imu-*.csv`` and the Vicon reference;
    ``leg="left"`` or ``"right"`` picks the leg when both have a reference),
    ``format="knee-rig"`` a KneeAngleAlgorithmComparison rig log. With
    ``calibration`` (a ``Calibration`` from ``calibrate`` or its file) the raw
    channels are calibrated first (``--calibration``). The result is the
    trial the CLI writes, value for value; it has no ``source`` (it was not
    read from a trial file)."""
    if not isinstance(format, str):
        raise TypeError(f'import_recording: format: expected "gaittoolbox" or "knee-rig", found {format!r}')
    if leg is not None and not isinstance(leg, str):
        raise TypeError(f'import_recording: leg: expected "left" or "right", found {leg!r}')
    cal: Optional[Tuple[str, str]] = None
    if isinstance(calibration, Calibration):
        cal = (calibration.toml, "<Calibration>")
    elif isinstance(calibration, (str, os.PathLike)):
        name = os.fspath(calibration)
        try:
            with open(name, encoding="utf-8") as f:
                cal = (f.read(), name)
        except OSError as e:
            raise _native.LimbfuseError(f"import_recording: calibration: cannot read {name}: {e.strerror}") from None
    elif calibration is not None:
        raise TypeError(
            "import_recording: calibration: expected a Calibration (limbfuse.calibrate) or its file, found "
            f"{type(calibration).__name__}"
        )
    return Trial._from_native(_native.import_recording(os.fsdecode(path), format, leg, cal))


def tune(
    trial: Trial,
    method: str,
    window: Union[str, Tuple[Optional[float], Optional[float]]],
    *,
    params: Union[None, PathLike, Mapping[str, Any]] = None,
    preset: str = "default",
    validate: Union[None, str, Tuple[Optional[float], Optional[float]]] = None,
    seed: int = 1,
    budget: int = 400,
    particles: int = 20,
    starts: int = 50,
    length: Optional[float] = None,
) -> Dict[str, Any]:
    """Tunes the noise parameters of ``local``, ``mjls`` or ``global`` on a
    window of a trial with reference angles (``limbfuse tune``; paper 001's
    protocol, docs/TUNING.md): a particle swarm (``seed``, ``budget``
    evaluations, ``particles``) minimising the mean segment RMSE over
    ``starts`` runs from starting points in ``window`` (``"0:20"`` or
    ``(0, 20)`` s; each run ``length`` s, default half the window), started
    from ``params`` (a parameter file, its text or a dict, as ``estimate``
    takes them) or ``preset`` (``"default"`` or ``"paper-2014"``), and
    scored on ``validate`` (default the block of the window's length right
    after it; ``"none"`` for none).

    Returns a dict: ``params`` (the parameter file's text, for
    ``estimate(..., params=...)`` or a file: the CLI's file but its first
    comment line), ``table`` (the CLI's RMSE table), ``tuning_rmse_deg`` and
    ``validation_rmse_deg`` (mean segment RMSE before and after),
    ``tuning_window``, ``validation_window``, ``dims``, ``evaluations`` and
    ``warnings`` (also given as ``LimbfuseWarning``s: a validation window
    overlapping the tuning one, tuned parameters worse than the start on
    it).

    ``sdre`` and ``ekf`` (``limbfuse tune --method sdre|ekf``, docs/
    FES_ESTIMATION.md): ``params`` is the extended knee model (a file, its
    text or a dict with ``[states]`` or ``[measurement]``), ``trial`` a
    pre-trial with ``u_ke`` and ``knee_ref``; its ``[tuning]
    torque_error`` is chosen among fixed candidates by leave-one-pulse-out
    cross-validation within ``window`` (the swarm's options do not apply).
    The dict then has ``params`` (the model with the chosen torque error,
    the CLI's file but its first comment line), ``table`` (what the CLI
    prints), ``torque_errors`` and ``rmse_deg`` (each candidate's knee RMSE
    over all pulse windows, infinite where it diverged), ``torque_error``,
    ``cv_rmse_deg``, ``pulse_windows`` and ``warnings`` (none)."""
    if not isinstance(trial, Trial):
        raise TypeError(f"tune: expected a limbfuse.Trial, found {type(trial).__name__}")
    if not isinstance(method, str):
        raise TypeError(f"tune: method: expected a method name, found {method!r}")
    win = _window_text(window)
    if win is None:
        raise _native.LimbfuseError("tune: window: expected \"START:END\" or (start, end) in seconds, found None")
    val = validate if validate is None or validate == "none" else _window_text(validate)
    counts = {"seed": seed, "budget": budget, "particles": particles, "starts": starts}
    for name, value in counts.items():
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            raise TypeError(f"tune: {name}: expected a non-negative integer, found {value!r}")
    if seed > 2**64 - 1:
        raise _native.LimbfuseError(f"tune: seed: expected at most 2^64 - 1 (a 64-bit seed), found {seed}")
    span = None if length is None else _number("tune: length", length)
    p = os.fsdecode(params) if isinstance(params, (str, bytes, os.PathLike)) else params
    out = dict(
        _native.tune(trial._native(), method, win, p, preset, val, seed, budget, particles, starts, span)
    )
    for line in out["warnings"]:
        warnings.warn(line, LimbfuseWarning, stacklevel=2)
    return out


def _number(name: str, value: Any) -> float:
    """A number option of ``gait_library``, named when it is not one (an
    audit: "could not convert string to float: 'a'")."""
    try:
        if isinstance(value, (str, bytes)):
            raise TypeError
        return float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected a number, found {value!r}") from None


def _numbers(name: str, values: Any) -> List[float]:
    try:
        items = list(values)
    except TypeError:
        raise TypeError(f"{name}: expected a sequence of numbers, found {values!r}") from None
    return [_number(f"{name}[{i}]", v) for i, v in enumerate(items)]


def report(
    trial: Union[PathLike, Trial],
    estimates: Union[PathLike, Estimate, Sequence[Union[PathLike, Estimate]]],
    path: PathLike,
    buckets: SupportsIndex = 2000,
    allow_trial_mismatch: bool = False,
    window: Union[None, str, Tuple[Optional[float], Optional[float]]] = None,
    offset_free: bool = False,
    max_lag: SupportsIndex = 0,
) -> int:
    """Writes the self-contained HTML report of ``limbfuse report`` (plots,
    error tables, method panels; docs/REPORT.md) to `path` and returns its
    size in bytes.

    `trial` and each of `estimates` (or one estimate) is a file path or an in-memory
    ``Trial`` / ``Estimate``; objects are written to a temporary folder
    first (their legend labels are then ``METHOD.csv``). With an in-memory
    trial the check that every estimate was made from it is skipped (it
    compares the trial file's content hash), as ``allow_trial_mismatch``
    does.

    ``window``, ``offset_free`` and ``max_lag`` are ``evaluate``'s (and the
    CLI's ``--window``, ``--offset-free``, ``--max-lag``): the error tables
    and the error over the gait cycle are scored with them, and the page
    states them.

    Raises:
        LimbfuseError: unreadable file, an estimate of another trial or of
            another length, ``buckets`` < 1, a scoring option that applies
            to no estimate, a ``max_lag`` over half the trial.
    """
    # (one estimate: a string is not a list of them)
    given: Sequence[Union[PathLike, Estimate]] = (
        [estimates] if isinstance(estimates, (str, bytes, os.PathLike, Estimate)) else estimates
    )
    buckets = count("buckets", buckets, 1, 2**31 - 1)
    allow_trial_mismatch = flag("allow_trial_mismatch", allow_trial_mismatch)
    # (as `evaluate`'s checks)
    max_lag = min(count("max_lag", max_lag, 0, None), 2**32)
    offset_free = flag("offset_free", offset_free)
    window_text = _window_text(window)
    with tempfile.TemporaryDirectory(prefix="limbfuse-report-") as tmp:
        if isinstance(trial, Trial):
            trial_path = os.path.join(tmp, "trial.csv")
            trial.write(trial_path)
            allow_trial_mismatch = True
        else:
            trial_path = os.fsdecode(trial)
        paths: List[str] = []
        for k, e in enumerate(given):
            if isinstance(e, Estimate):
                if any(e is x for x in given[:k]):
                    raise _native.LimbfuseError(
                        f"report: estimate {k} is estimate {next(j for j, x in enumerate(given) if x is e)} "
                        "given again; give each estimate once"
                    )
                # (the method names a file in the temporary folder: only
                # name characters, never a path; an audit wrote outside it
                # with method="../x")
                stem = re.sub(r"[^A-Za-z0-9_.-]", "_", e.method).lstrip(".") or "estimate"
                name = f"{stem}.csv"
                if any(os.path.basename(p) == name for p in paths):
                    name = f"{stem}-{k}.csv"
                p = os.path.join(tmp, name)
                e.write(p)
                paths.append(p)
            else:
                paths.append(os.fsdecode(e))
        # (the scoring options as given, so that the page states them)
        scoring = "".join(
            f", {k}={v!r}"
            for k, v, given in (
                ("window", window_text, window_text is not None),
                ("offset_free", offset_free, offset_free),
                ("max_lag", max_lag, max_lag > 0),
            )
            if given
        )
        command = f"limbfuse.report({os.path.basename(trial_path)!r}, {len(paths)} estimate(s){scoring}) (Python)"
        return int(
            _native.report(
                trial_path,
                paths,
                os.fsdecode(path),
                buckets,
                allow_trial_mismatch,
                command,
                window_text,
                offset_free,
                max_lag,
            )
        )
