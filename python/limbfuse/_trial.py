"""`Trial`: a trial (SPEC section 2) as numpy arrays, and its file I/O."""

from __future__ import annotations

import os
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Dict, Mapping, Optional, Tuple, Union

import numpy as np

from . import _native
from ._arrays import SetOnce, as_column, as_time, filled, from_native, frozen, phase_array, phase_cells
from ._lazy import LazyModule

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
else:  # (pandas is imported on first use; `_lazy`)
    pd = LazyModule("pandas")

PathLike = Union[str, "os.PathLike[str]"]

PHASE_REF = "phase_ref"


class Trial(SetOnce):
    """One recorded or simulated trial.

    Attributes:
        t: time (s), float64, strictly increasing.
        channels: read-only mapping of SPEC column name (``thigh_gyr_x``,
            ``knee_enc``, ``thigh_ref``, the other leg's ``foot_left_gyr_x``
            (named after ``meta["leg"]``, right when absent),
            ``contact_left_ref`` (1 / 0), ``speed_ref``, ...) to a float64
            array; an array with missing samples is a ``numpy.ma.MaskedArray``.
            ``t`` and the arrays are read-only views, and the attributes
            cannot be replaced (checked when the trial was made: build a
            new ``Trial`` to change them).
        phase_ref: the gait-phase reference (``"SS1"``, ``"DS"``, ``"SS2"``
            or None) as an object array, or None when the trial has none.
        meta: the ``# key: value`` header (units and conventions of SPEC).
        source: ``(file name, content hash)`` when read from a file (an
            estimate made from it records both, as the CLI's does).

    Build one from arrays, ``Trial(t, {"thigh_gyr_x": gx, ...}, meta)``, or
    from a DataFrame, ``Trial.from_pandas(df)``. Arrays are checked: a
    non-numeric dtype raises ``TypeError``; a wrong length, an unknown or
    incomplete channel group, non-increasing time or an unmasked NaN raises
    ``LimbfuseError``. Arrays already float64 and contiguous are not copied.
    """

    __slots__ = ("t", "channels", "phase_ref", "meta", "source")
    t: np.ndarray
    channels: Mapping[str, np.ndarray]
    phase_ref: Optional[np.ndarray]
    meta: Dict[str, str]
    source: Optional[Tuple[str, str]]

    def __init__(
        self,
        t: Any,
        channels: Mapping[str, Any],
        meta: Optional[Mapping[str, Any]] = None,
        phase_ref: Any = None,
        *,
        source: Optional[Tuple[str, str]] = None,
    ) -> None:
        if not hasattr(channels, "items"):
            raise TypeError(
                f"channels: expected a mapping of channel name to array, found {type(channels).__name__}"
            )
        index = _pandas_index(t)
        t = as_time(t)
        for name in channels:
            if not isinstance(name, str):
                raise TypeError(f"channel names must be str, found {name!r}")
        # (the names before the arrays: a misspelt channel holding a NaN was
        # reported as the NaN; session 32. A block of axes keeps its shape
        # message, which names the channels to split it into.)
        _native.check_channel_names(
            [(str(k), str(v)) for k, v in (meta or {}).items()],
            [n for n, v in channels.items() if n != PHASE_REF and _ndim(v) == 1],
        )
        cols: Dict[str, np.ndarray] = {}
        for name, values in channels.items():
            _check_rows(name, values, index)
            if name == PHASE_REF:
                if phase_ref is not None:
                    raise _native.LimbfuseError("`phase_ref` is given twice")
                phase_ref = values
                continue
            cols[name] = as_column(name, values, t.shape[0])
        self.t = frozen(t)
        self.channels = MappingProxyType({n: frozen(a) for n, a in cols.items()})
        self.phase_ref = (
            None if phase_ref is None else phase_array(phase_cells(PHASE_REF, phase_ref, t.shape[0]))
        )
        self.meta = {str(k): str(v) for k, v in (meta or {}).items()}
        self.source = source
        _native.check_trial(self._native())

    def _native(self) -> tuple:
        names = list(self.channels)
        return (
            list(self.meta.items()),
            self.t,
            names,
            [filled(self.channels[n]) for n in names],
            None if self.phase_ref is None else list(self.phase_ref),
            self.source,
        )

    @classmethod
    def _from_native(cls, tup: tuple) -> "Trial":
        meta, t, names, arrays, phase, source = tup
        trial = cls.__new__(cls)
        trial.t = frozen(t)
        trial.channels = MappingProxyType({n: frozen(from_native(a)) for n, a in zip(names, arrays)})
        trial.phase_ref = phase_array(phase)
        trial.meta = dict(meta)
        trial.source = source
        return trial

    @classmethod
    def from_pandas(cls, df: "pd.DataFrame", meta: Optional[Mapping[str, Any]] = None) -> "Trial":
        """A trial from a DataFrame with a ``t`` column and SPEC channel
        columns (NaN = missing sample); ``meta`` defaults to ``df.attrs["meta"]``."""
        if not hasattr(df, "columns") or not hasattr(df, "attrs"):
            raise TypeError(f"from_pandas: expected a pandas DataFrame, found {type(df).__name__}")
        if df.columns.nlevels > 1:
            raise _native.LimbfuseError(
                f"the DataFrame's columns have {df.columns.nlevels} levels (a MultiIndex); "
                "expected one name per column (`t` and SPEC channel names): flatten them first, "
                "e.g. `df.columns = df.columns.get_level_values(-1)`"
            )
        if "t" not in df.columns and df.index.name == "t":
            df = df.reset_index()  # (time as the index, as `set_index("t")` leaves it)
        if "t" not in df.columns:
            kind = getattr(df.index.dtype, "kind", "")
            hint = (
                f"; its index `{df.index.name}` holds {df.index.dtype} times: name it `t` "
                "(`df.rename_axis(\"t\")`; durations are taken as seconds, dates are refused)"
                if kind in "mM" and kind
                else ""
            )
            raise _native.LimbfuseError(f"the DataFrame has no `t` column or index (time in seconds){hint}")
        repeated = df.columns[df.columns.duplicated()]
        if len(repeated):
            # (an audit: AttributeError "'DataFrame' object has no attribute 'dtype'")
            raise _native.LimbfuseError(
                f"the DataFrame has the column `{repeated[0]}` more than once; keep one "
                "(e.g. `df.loc[:, ~df.columns.duplicated()]`)"
            )
        channels: Dict[str, Any] = {}
        phase = None
        for name in df.columns:
            if name == "t":
                continue
            col = df[name]
            if name == PHASE_REF:
                phase = col.to_numpy(dtype=object)
                continue
            if getattr(col.dtype, "kind", "O") not in "biuf":
                raise TypeError(
                    f"channel `{name}`: expected a numeric (or bool) column, found dtype {col.dtype}"
                )
            channels[str(name)] = col  # NaN = missing (`as_column`)
        if meta is None:
            meta = df.attrs.get("meta", {})
        # (the Series: its dtype names a Timedelta / datetime / Float64 `t`)
        return cls(df["t"], channels, meta, phase)

    def to_pandas(self) -> "pd.DataFrame":
        """The trial as a DataFrame (missing samples are NaN; ``attrs["meta"]``
        holds the metadata)."""
        import pandas as pd

        data: Dict[str, Any] = {"t": self.t}
        for name, a in self.channels.items():
            data[name] = filled(a)
        if self.phase_ref is not None:
            data[PHASE_REF] = self.phase_ref
        df = pd.DataFrame(data)
        df.attrs["meta"] = dict(self.meta)
        return df

    def write(self, path: PathLike) -> None:
        """Writes the trial file (the same bytes ``limbfuse`` writes)."""
        _native.write_trial(os.fsdecode(path), self._native())

    def __len__(self) -> int:
        return int(self.t.shape[0])

    def __getitem__(self, rows: slice) -> "Trial":
        """Consecutive samples as a new trial: ``trial[100:600]`` (by sample
        index; ``trial.window(t0, t1)`` by time). The metadata is kept, the
        file it came from is not (``source`` is None: an estimate of the
        slice does not record the file's hash)."""
        if not isinstance(rows, slice):
            raise TypeError(f"a Trial is sliced by samples, trial[a:b]; found {type(rows).__name__}")
        if rows.step not in (None, 1):
            raise _native.LimbfuseError(
                f"trial[a:b:{rows.step}]: a step would change the sample rate; use `limbfuse resample`"
            )
        rows = slice(rows.start, rows.stop)
        if len(self.t[rows]) == 0:
            raise _native.LimbfuseError(f"trial[{rows.start}:{rows.stop}]: no samples (the trial has {len(self)})")
        phase = None if self.phase_ref is None else self.phase_ref[rows]
        return Trial(self.t[rows], {k: v[rows] for k, v in self.channels.items()}, self.meta, phase)

    def window(self, start: Optional[float] = None, end: Optional[float] = None) -> "Trial":
        """The samples with ``start <= t < end`` (s; either end open), as
        ``trial[a:b]``."""
        for name, v in (("start", start), ("end", end)):
            if v is not None and (isinstance(v, (bool, str, bytes)) or not np.isfinite(v)):
                raise _native.LimbfuseError(f"window: `{name}` = {v!r}: expected a time in seconds or None (open)")
        a = 0 if start is None else int(np.searchsorted(self.t, start, side="left"))
        b = len(self) if end is None else int(np.searchsorted(self.t, end, side="left"))
        return self[a:b]

    def __reduce__(self) -> tuple:
        # pickle, copy.deepcopy, multiprocessing (an audit: "cannot pickle
        # 'mappingproxy' object"); the arrays are checked again on the way in.
        return (_trial_from_state, (self.t, dict(self.channels), self.meta, self.phase_ref, self.source))

    def __repr__(self) -> str:
        src = f" from {self.source[0]}" if self.source else ""
        return f"<Trial{src}: {len(self)} samples, {len(self.channels)} channels>"


def _pandas_index(values: Any) -> Any:
    """The row labels of a pandas Series (None for anything else)."""
    if type(values).__module__.startswith("pandas") and getattr(values, "ndim", 0) == 1:
        return getattr(values, "index", None)
    return None


def _check_rows(name: str, values: Any, index: Any) -> None:
    """A channel given as a pandas Series beside a Series `t`: its rows
    must be `t`'s, label for label. Arrays pair by position, so a Series
    from another (filtered, sorted, re-indexed) DataFrame would silently
    pair `t[i]` with another row's value (an audit: `Trial(df["t"],
    {"knee_enc": other["knee_enc"]})` with `other` sorted otherwise was
    accepted)."""
    theirs = _pandas_index(values)
    if index is None or theirs is None or index.equals(theirs):
        return
    raise _native.LimbfuseError(
        f"channel `{name}`: its pandas index is not `t`'s (rows from another DataFrame, or "
        "reordered); values pair with times by position: take both from one DataFrame, "
        "align them (`.reindex(t.index)`), or pass `.to_numpy()` to pair by position"
    )


def _ndim(values: Any) -> int:
    """Dimensions of a channel's values (an array's own, else numpy's
    reading of a list: a list of rows is a block of axes)."""
    return values.ndim if hasattr(values, "ndim") else np.ndim(values)


def _trial_from_state(t, channels, meta, phase_ref, source) -> Trial:
    return Trial(t, channels, meta, phase_ref, source=source)


def read_trial(path: PathLike) -> Trial:
    """Reads a trial file. Errors name the file, line and column. A last
    line cut off while the file was written (fewer cells than the header,
    no line break) is left out with a ``LimbfuseWarning``."""
    return Trial._from_native(_native.read_trial(os.fsdecode(path)))


def write_trial(trial: Trial, path: PathLike) -> None:
    """Writes `trial` to `path` (as ``Trial.write``)."""
    trial.write(path)
