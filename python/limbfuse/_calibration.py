"""`Calibration`: a sensor calibration file's text in memory, and the
``calibration=`` option it serves (apart from `_workflows`, so that
`_estimate` and `_filter` use it without importing `_workflows`, which
imports them: no import cycle, and every annotation resolves at run time for
``typing.get_type_hints``)."""

from __future__ import annotations

import os
from typing import Any, Dict, List

from ._trial import PathLike


class Calibration:
    """A sensor calibration (``limbfuse calibrate``): ``toml`` is the file's
    text, ``sensors`` one summary dict per calibrated IMU (segment, poses,
    residual_mg, acc_bias_mg, acc_scale, gyro_bias_rad_s, rejected).
    ``write(path)`` writes the file ``limbfuse estimate --calibration``,
    ``import --calibration`` and ``align --imu-calibration`` read
    (docs/CALIBRATION.md); ``estimate(..., calibration=cal)`` and
    ``align(..., imu_calibration=cal)`` take it as it is."""

    def __init__(self, toml: str, sensors: List[Dict[str, Any]]):
        self.toml = toml
        self.sensors = sensors

    def write(self, path: PathLike) -> None:
        """Writes the calibration file (``toml``) to `path`."""
        with open(os.fspath(path), "w", encoding="utf-8") as f:
            f.write(self.toml)

    def __repr__(self) -> str:
        names = ", ".join(str(s["segment"]) for s in self.sensors)
        return f"<Calibration of {names}>"


def calibration_options(options: Dict[str, Any]) -> Dict[str, Any]:
    """The native options of ``calibration=`` (``estimate``, ``Filter``): a
    ``Calibration`` passes its text as ``calibration_toml``, a path as a
    string; anything else is left for the native layer to reject."""
    cal = options.get("calibration")
    if isinstance(cal, Calibration):
        options = dict(options)
        options["calibration_toml"] = options.pop("calibration").toml
    elif isinstance(cal, os.PathLike):
        options = dict(options, calibration=os.fspath(cal))
    return options
