"""`Filter`: a method's estimator kept between calls, for real-time use."""

from __future__ import annotations

import math
import os
import warnings
from typing import TYPE_CHECKING, Any, Dict, Iterable, List, Mapping, Optional, Union, cast

import numpy as np

from . import _native
from ._arrays import _is_pandas
from ._calibration import calibration_options
from ._estimate import Estimate, LimbfuseWarning
from ._lazy import LazyModule
from ._trial import PathLike, Trial

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
else:  # (pandas is imported on first use; `_lazy`)
    pd = LazyModule("pandas")


class Filter:
    """One estimator, stepped sample by sample or run over arrays.

    ``Filter("mjls", channels=trial.channels, meta=trial.meta)`` builds the
    method for a trial with those channels (``Filter.for_trial`` does the
    same from a trial). A method that needs a channel not in ``channels``
    raises ``LimbfuseError`` here, naming the channel.

    ``step({"t": 0.01, "thigh_gyr_x": ..., ...})`` returns a dict of the
    estimate's columns (``None`` = not estimated); a channel absent from the
    sample or ``None`` is a missing sample. ``run({"t": t, ...})`` runs over
    arrays with the GIL released and returns an ``Estimate``. Both continue
    from the filter's state; ``reset()`` starts over.

    ``calibration=`` (a calibration file or a ``Calibration``, as
    ``estimate``'s) is applied to every IMU reading before the method sees
    it.
    """

    def __init__(
        self,
        method: str,
        params: Union[None, PathLike, Mapping[str, Any]] = None,
        *,
        channels: Iterable[str],
        meta: Optional[Mapping[str, Any]] = None,
        **options: Any,
    ) -> None:
        p = os.fsdecode(params) if isinstance(params, (str, bytes, os.PathLike)) else params
        if isinstance(channels, (str, bytes)):
            raise TypeError(
                f"channels: expected a sequence of channel names, found the string {channels!r} "
                "(one channel: [name])"
            )
        try:
            names = [str(c) for c in channels]
        except TypeError:
            raise TypeError(
                f"channels: expected a sequence of channel names, found {type(channels).__name__}"
            ) from None
        # `run` checks its arrays as a trial with this metadata (the `leg`
        # names the other leg's channels).
        self._meta = {str(k): str(v) for k, v in (meta or {}).items()}
        options = calibration_options(options)
        self._native = _native.NativeFilter(
            method,
            names,
            [(str(k), str(v)) for k, v in (meta or {}).items()],
            p,
            options or None,
        )
        # `estimate`'s warning: a method reading aligned frames, metadata
        # declaring raw ones (`# imu_frame: raw ...`) and no alignment.
        if self._native.frame_note:
            warnings.warn(self._native.frame_note, LimbfuseWarning, stacklevel=2)

    @classmethod
    def for_trial(
        cls,
        trial: Trial,
        method: str,
        params: Union[None, PathLike, Mapping[str, Any]] = None,
        **options: Any,
    ) -> "Filter":
        """A filter for trials with `trial`'s channels and metadata."""
        return cls(method, params, channels=list(trial.channels), meta=trial.meta, **options)

    @property
    def channels(self) -> List[str]:
        """The channels the filter reads."""
        return list(self._native.channels)

    @property
    def header(self) -> List[str]:
        """The method and its parameters (estimate file header lines)."""
        return list(self._native.header)

    def step(self, sample: Union[Mapping[str, Any], "pd.Series"]) -> Dict[str, Any]:
        """One sample in, one estimate out. A missing value is ``None``,
        ``numpy.ma.masked`` or an absent key (NaN is refused: limbfuse never
        takes NaN for a value); a value that is not a number raises
        ``TypeError``. A pandas Series (a DataFrame's row, ``df.iloc[i]``)
        is read as ``run`` reads a DataFrame: NaN is missing, and a
        ``phase_ref`` label (a reference, which no method reads) is left
        out."""
        if _is_pandas(sample) and getattr(sample, "ndim", 0) == 1:
            # (an audit, session 31: a row of `trial.to_pandas()` raised
            # "NaN is not a value" for its unknown references, and "found
            # 'SS1'" for a gait trial's `phase_ref`)
            row: Dict[Any, Any] = {
                k: (None if isinstance(v, (float, np.floating)) and math.isnan(v) else v)
                for k, v in sample.items()
                if k != "phase_ref"
            }
            sample = row
        if not isinstance(sample, dict):
            try:
                sample = dict(sample)
            except (TypeError, ValueError):
                raise TypeError(
                    f"step: expected a dict of channel name -> value (and `t`), found {type(sample).__name__}"
                ) from None
        try:
            return self._native.step(sample)
        except RuntimeError as e:
            if isinstance(e, _native.InternalError):
                raise
            raise _busy(e) from None

    def run(self, arrays: Union[Mapping[str, Any], "pd.DataFrame"]) -> Estimate:
        """Runs over arrays (``t`` and channels; masked = missing) or a
        DataFrame's columns (NaN = missing), the GIL released; returns the
        estimates as an ``Estimate``."""
        if "t" not in arrays:
            raise _native.LimbfuseError("run: the arrays need `t` (time in seconds)")
        # (a column name that is not a string is refused by `Trial`, named)
        rest = cast(Mapping[str, Any], {k: v for k, v in arrays.items() if k != "t"})
        data = Trial(arrays["t"], rest, self._meta)
        _, t, names, filled, _, _ = data._native()
        try:
            return Estimate._from_native(self._native.run(t, names, filled))
        except RuntimeError as e:
            if isinstance(e, _native.InternalError):
                raise
            raise _busy(e) from None

    def reset(self) -> None:
        """Forgets the state: the next sample starts a new run."""
        self._native.reset()

    # A filter is a running estimator's state (in the extension): it is
    # neither copied nor pickled. An audit: `copy.copy(f)` shared that state,
    # so stepping the copy moved the original; `pickle` and `deepcopy`
    # said only "cannot pickle 'limbfuse._native.NativeFilter' object".
    def __copy__(self) -> "Filter":
        raise TypeError(_NOT_COPIED)

    def __deepcopy__(self, memo: Any) -> "Filter":
        raise TypeError(_NOT_COPIED)

    def __reduce__(self) -> Any:
        raise TypeError(_NOT_COPIED)


_NOT_COPIED = (
    "a limbfuse.Filter cannot be copied or pickled: it holds a running estimator's state; "
    "make another with Filter(...) or Filter.for_trial(...) (e.g. one per process) and feed "
    "it the samples"
)


def _busy(e: RuntimeError) -> RuntimeError:
    """PyO3's "Already borrowed": a filter stepped from two threads at once."""
    if "borrow" in str(e).lower():
        return RuntimeError(
            "this Filter is in use by another thread: a filter is stepped by one thread at a "
            "time (make one Filter per thread, or guard it with a lock)"
        )
    return e
