"""`montecarlo`: paper 000 Fig. 9 on simulated walking, as a function."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Optional, Sequence, Union

from . import _native
from ._lazy import LazyModule
from ._trial import PathLike

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
else:  # (pandas is imported on first use; `_lazy`)
    pd = LazyModule("pandas")


def montecarlo(
    runs: int = 100,
    levels: Union[None, str, Sequence[float]] = None,
    *,
    seed: int = 1,
    speed: float = 1.0,
    duration: float = 30.0,
    svg: Optional[PathLike] = None,
    progress: bool = False,
) -> pd.DataFrame:
    """The segment filters under parametric uncertainty (``limbfuse
    montecarlo``; paper 000 section 4, Fig. 9; docs/RESULTS.md, "Monte Carlo under
    parametric uncertainty"): each of
    ``runs`` simulated walks (``seed + r``, ``speed`` m/s, ``duration`` s) is
    estimated by ``local``, ``mjls`` and ``global`` with every noise
    parameter multiplied by ``1 + L u`` (``u`` uniform in [-1, 1]) at each
    uncertainty level ``L``: ``levels`` in percent, ``"START:END:STEP"``
    (default ``"0:20:2"``) or a sequence such as ``[0, 5, 10]``.

    Returns one row per filter and level, the CLI's CSV columns
    (``method``, ``level_pct``, ``mean_rmse_deg``, ``std_rmse_deg``,
    ``runs``: the mean and standard deviation over runs of the 4-segment
    mean RMSE), the same numbers as the CLI's file for the same settings;
    ``df.attrs["csv"]`` is that file's text (with ``# version``, ``#
    command`` and ``# trial_seeds`` lines naming this call). ``svg``: also
    draw the plot there. ``progress``: show ``montecarlo: N/M runs`` on
    ``sys.stderr`` as the runs end (the CLI draws a bar). Runs use every
    core (rayon); the rows do not depend on their number. Ctrl-C stops it
    (``KeyboardInterrupt``)."""
    for name, value in (("runs", runs), ("seed", seed)):
        if isinstance(value, bool) or not isinstance(value, int):
            raise TypeError(f"montecarlo: {name}: expected an int, found {value!r}")
    if not 0 <= seed <= 2**64 - 1:
        raise _native.LimbfuseError(f"montecarlo: seed = {seed}: expected a seed from 0 to 2^64 - 1 (64 bits)")
    if runs < 1:
        raise _native.LimbfuseError(f"montecarlo: runs = {runs}: expected at least 1 run per level")
    for name, number in (("speed", speed), ("duration", duration)):
        if isinstance(number, bool) or not isinstance(number, (int, float)):
            raise TypeError(f"montecarlo: {name}: expected a number, found {number!r}")
    out = _native.montecarlo(
        runs,
        levels,
        seed,
        float(speed),
        float(duration),
        None if svg is None else os.fspath(svg),
        bool(progress),
    )
    import pandas as pd

    df = pd.DataFrame({k: out[k] for k in ("method", "level_pct", "mean_rmse_deg", "std_rmse_deg", "runs")})
    df.attrs["csv"] = out["csv"]
    df.attrs["provenance"] = out["provenance"]
    return df
