"""`simulate`, `align`, `gait_library`: the CLI's workflows as functions.

`calibrate` (issue 17) joins these when the calibration workflow exists in
the Rust crates: a `calibrate` function in `src/workflows.rs` registered
beside `align`, wrapped here the same way.
"""

from __future__ import annotations

import os
from typing import Any, Dict, List, Sequence

from . import _native
from ._trial import PathLike, Trial


def simulate(kind: str = "walking", **options: Any) -> Trial:
    """Simulates a trial in memory, as ``limbfuse simulate KIND`` does.

    kinds and options (defaults are the CLI's):
        walking: speed, duration, imu_rate, seed, mounting ("aligned" or
            "random"), noise, out_of_plane, variability.
        knee: speed, duration, imu_rate, seed, noise, out_of_plane (paper 002
            scenario: random IMU orientations and positions).
        knee-fes: subject ("P1-L" ... "P3-R"), duration, rate, seed, noise,
            mounting (paper 004).
        fixed-hip: duration, rate, seed, noise (paper 004).
    """
    return Trial._from_native(_native.simulate(kind, options or None))


def align(trial: Trial, **options: Any) -> Trial:
    """Sensor-to-segment alignment from walking data (``limbfuse align``):
    the aligned trial, its metadata annotated with the rotations.

    options: hinge (bool), partial (bool), mean_angle ({segment: degrees},
    the walking mean angle when the trial has no quiet standing).
    """
    if not isinstance(trial, Trial):
        raise TypeError(f"align: expected a limbfuse.Trial, found {type(trial).__name__}")
    return Trial._from_native(_native.align(trial._native(), options or None))


def gait_library(
    path: PathLike, speeds: Sequence[float], mass: float = 80.0, leg_length: float = 1.0
) -> List[Dict[str, float]]:
    """Builds a B-SLIP gait library (``limbfuse gait-library build``) for
    `speeds` (m/s), writes it to `path` (for ``estimate(..., "imm-bslip",
    library=path)``) and returns one summary per gait."""
    return list(_native.gait_library(os.fspath(path), [float(s) for s in speeds], float(mass), float(leg_length)))
