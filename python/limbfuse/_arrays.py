"""Checks and conversions of the numpy arrays that cross into the extension.

A missing sample is a masked element (``numpy.ma``) in arrays and NaN in a
pandas DataFrame (pandas' own missing marker). A bare NaN or inf in a numpy
array is refused: limbfuse never takes NaN for a value.
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from ._native import LimbfuseError

PHASE_LABELS = ("SS1", "DS", "SS2")


class SetOnce:
    """Public attributes set once, when the object is made (``Trial``,
    ``Estimate``): their arrays were checked together, so replacing one
    (an audit: ``trial.t = np.zeros(3)`` left 3 times beside 500-sample
    channels) raises ``AttributeError``; build a new object instead."""

    __slots__ = ()

    def __setattr__(self, name: str, value: Any) -> None:
        if not name.startswith("_") and hasattr(self, name):
            kind = type(self).__name__
            raise AttributeError(
                f"{kind}.{name} is read-only: its arrays were checked together when the "
                f"{kind} was made; build a new {kind} to change it"
            )
        object.__setattr__(self, name, value)

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"{type(self).__name__}.{name} cannot be deleted")


def as_column(name: str, values: Any, n: Optional[int]) -> np.ndarray:
    """A 1-D float64 array of `values` (masked where missing), checked.

    Raises ``TypeError`` for a non-numeric dtype and ``LimbfuseError`` for a
    wrong shape or length, or an unmasked NaN/inf.
    """
    if np.ma.isMaskedArray(values):
        data = np.ma.getdata(values)
        mask = np.ma.getmaskarray(values)
    elif _is_pandas(values) and getattr(values, "ndim", 1) != 1:
        # (a DataFrame: `df[["knee_enc"]]`, or a name given twice in a
        # DataFrame; an audit: AttributeError "'DataFrame' object has no
        # attribute 'dtype'")
        raise TypeError(
            f"channel `{name}`: expected one column (a Series or a 1-D array), found a "
            f"{type(values).__name__} of {getattr(values, 'shape', '?')}"
        )
    elif _is_pandas(values):
        # pandas' missing marker is NaN (or NA/None): missing here too (an
        # audit: `Trial(df["t"], {c: df[c]})` and `Filter.run(df)` refused
        # the NaN `from_pandas` takes).
        if getattr(values.dtype, "kind", "O") in "biuf":  # numpy or pandas (Int64, boolean) numbers
            data = values.to_numpy(dtype=np.float64, na_value=np.nan)
            mask = np.isnan(data)
        else:
            data = np.asarray(values)
            mask = None
    else:
        data = np.asarray(values)
        mask = None
    if data.dtype.kind == "b":
        data = data.astype(np.float64)  # contact columns: True = on the ground
    if data.dtype.kind not in "fiu":
        raise TypeError(
            f"channel `{name}`: expected a numeric (float or int) array, found dtype {data.dtype}"
        )
    if data.ndim != 1:
        raise LimbfuseError(
            f"channel `{name}`: expected a 1-D array, found shape {data.shape}{_axes_hint(name, data)}"
        )
    if n is not None and data.shape[0] != n:
        raise LimbfuseError(
            f"channel `{name}` has {data.shape[0]} samples but `t` has {n} "
            "(every channel needs one value per time)"
        )
    data = np.ascontiguousarray(data, dtype=np.float64)
    bad = ~np.isfinite(data)
    if mask is not None:
        bad &= ~mask
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise LimbfuseError(
            f"channel `{name}`, sample {i}: {data[i]} is not a value; mark missing samples "
            "with a masked array (numpy.ma) or with NaN in a pandas DataFrame"
        )
    if mask is not None and mask.any():
        return np.ma.MaskedArray(data, mask=mask)
    return data


def _is_pandas(values: Any) -> bool:
    """A pandas Series or Index (not imported: pandas is optional)."""
    return type(values).__module__.startswith("pandas") and hasattr(values, "to_numpy")


def fingerprint(t: np.ndarray, channels: Any) -> dict:
    """Digests of a trial's samples, for telling two in-memory trials apart:
    ``"t"`` (its length and values) and one per input channel (references
    such as ``knee_ref`` and the CoM truth left out), each over 257
    evenly spaced rows (NaN where masked): cheap for an hour-long trial.
    Compare with ``same_samples``."""
    import hashlib

    n = int(t.shape[0])
    idx = np.unique(np.linspace(0, max(n - 1, 0), num=min(n, 257)).astype(np.int64))

    def digest(*parts: bytes) -> bytes:
        h = hashlib.blake2b(digest_size=16)
        for b in parts:
            h.update(b)
        return h.digest()

    out = {"t": digest(np.int64(n).tobytes(), np.ascontiguousarray(t[idx], dtype=np.float64).tobytes())}
    for name, a in channels.items():
        if name.endswith("_ref") or (name.startswith("com_") and not name.startswith("com_meas")):
            continue  # references, not inputs: correcting them keeps the trial
        rows = np.ma.filled(np.ma.asarray(a[idx]).astype(np.float64), np.nan)
        out[name] = digest(np.ascontiguousarray(rows).tobytes())
    return out


def same_samples(a: dict, b: dict) -> bool:
    """Whether two ``fingerprint``s are of one trial: the same time base and
    the same values in every channel both have (a reference column added
    afterwards is still the same trial)."""
    return a["t"] == b["t"] and all(a[k] == b[k] for k in a.keys() & b.keys())


def as_time(t: Any) -> np.ndarray:
    """The time array: 1-D, numeric, finite (order is checked in Rust).
    Durations (``timedelta64``, a pandas ``TimedeltaIndex`` or Timedelta
    column) are converted to seconds; dates (``datetime64``) are refused
    with how to convert them."""
    kind = getattr(getattr(t, "dtype", None), "kind", None)
    if kind == "m":  # (an audit: a Timedelta `t` was "not numeric")
        seconds = np.asarray(t, dtype="timedelta64[ns]")
        missing = np.isnat(seconds)
        if missing.any():
            i = int(np.flatnonzero(missing)[0])
            raise LimbfuseError(f"`t`, sample {i}: time cannot be missing (NaT)")
        t = seconds / np.timedelta64(1, "s")
    elif kind == "M" or str(getattr(t, "dtype", "")).startswith("datetime64"):
        raise TypeError(
            "`t`: expected time in seconds, found dates and times "
            f"({getattr(t, 'dtype', '?')}); convert them to seconds from the start, e.g. "
            "`(ts - ts[0]) / numpy.timedelta64(1, 's')`, or for pandas "
            "`(df.index - df.index[0]).total_seconds()`"
        )
    if np.ma.isMaskedArray(t) and np.ma.getmaskarray(t).any():
        raise LimbfuseError("`t`: time cannot be missing (masked)")
    arr = as_column("t", np.ma.getdata(t) if np.ma.isMaskedArray(t) else t, None)
    if np.ma.isMaskedArray(arr):  # (NaN in a pandas time column)
        i = int(np.flatnonzero(np.ma.getmaskarray(arr))[0])
        raise LimbfuseError(f"`t`, sample {i}: time cannot be missing (NaN)")
    return np.asarray(arr)


def frozen(a: np.ndarray) -> np.ndarray:
    """A read-only view of `a` (data and mask): the arrays of a ``Trial`` or
    an ``Estimate`` were checked when it was made (no unmasked NaN), so
    they cannot be written afterwards. The array the caller passed in (not
    copied when already float64 and contiguous) stays writeable."""
    if np.ma.isMaskedArray(a):
        data = np.ma.getdata(a).view()
        mask = np.ma.getmaskarray(a).view()
        data.flags.writeable = False
        mask.flags.writeable = False
        return np.ma.MaskedArray(data, mask=mask)
    v = a.view()
    v.flags.writeable = False
    return v


def filled(a: np.ndarray) -> np.ndarray:
    """The float64 array the extension reads: NaN where masked (no copy for
    an unmasked contiguous float64 array)."""
    if np.ma.isMaskedArray(a):
        return np.ascontiguousarray(np.ma.filled(a.astype(np.float64), np.nan))
    return np.ascontiguousarray(a, dtype=np.float64)


def from_native(a: np.ndarray) -> np.ndarray:
    """An array from the extension (NaN = missing) as the public form:
    masked where missing, the plain array otherwise."""
    missing = np.isnan(a)
    if missing.any():
        return np.ma.MaskedArray(a, mask=missing)
    return a


def phase_cells(name: str, values: Any, n: int) -> List[Optional[str]]:
    """Gait-phase cells: ``SS1``, ``DS``, ``SS2``, or missing (None, "", NaN)."""
    cells = list(np.asarray(values, dtype=object))
    if len(cells) != n:
        raise LimbfuseError(f"channel `{name}` has {len(cells)} samples but `t` has {n}")
    out: List[Optional[str]] = []
    for i, c in enumerate(cells):
        if c is None or (isinstance(c, float) and np.isnan(c)) or c == "" or c is np.ma.masked:
            out.append(None)
        elif isinstance(c, str):
            out.append(c)
        else:
            raise LimbfuseError(
                f"channel `{name}`, sample {i}: expected a gait phase `SS1`, `DS` or `SS2`, found {c!r}"
            )
    return out


def phase_array(cells: Optional[Sequence[Optional[str]]]) -> Optional[np.ndarray]:
    """Phase cells as an object array (None = missing)."""
    if cells is None:
        return None
    return np.array(list(cells), dtype=object)


def split_header(lines: Sequence[str]) -> Tuple[Dict[str, str], Dict[str, str]]:
    """Header lines ``key: value`` -> (all entries, parameters only)."""
    entries: Dict[str, str] = {}
    for line in lines:
        k, sep, v = line.partition(":")
        if sep:
            entries[k.strip()] = v.strip()
    params = {k: v for k, v in entries.items() if k not in ("method", "trial", "trial_hash", "command")}
    return entries, params


def _axes_hint(name, data):
    """What to say of an N x 3 block given as one channel (peers' tools keep a
    sensor's three axes in one array; SPEC names one column per axis)."""
    if data.ndim != 2 or 3 not in data.shape:
        return ""
    base = name[:-2] if name[-2:] in ("_x", "_y", "_z") else name
    cols = "a[:, {}]" if data.shape[1] == 3 else "a[{}]"
    pairs = ", ".join(f"'{base}_{axis}': {cols.format(k)}" for k, axis in enumerate("xyz"))
    return (
        f"; a sensor's three axes are three channels `{base}_x`, `{base}_y`, `{base}_z` "
        f"(SPEC column names): pass {{{pairs}}}"
    )
