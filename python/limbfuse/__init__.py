"""limbfuse: lower-limb state estimation from IMUs and exoskeleton encoders.

The Python face of the limbfuse Rust toolkit (tutorial: docs/python.md):

    import limbfuse
    trial = limbfuse.read_trial("trial.csv")        # or simulate(), Trial(...)
    est = limbfuse.estimate(trial, "mjls")          # every method of the CLI
    limbfuse.evaluate(trial, est)["rmse_deg"]       # = limbfuse evaluate --json
    est.to_pandas()

Missing samples are masked (``numpy.ma``) in arrays and NaN in DataFrames.
User errors raise ``LimbfuseError`` (a ``ValueError``) with the CLI's
message; a limbfuse bug raises ``InternalError``; no Rust panic escapes.
"""

from types import ModuleType
from typing import TYPE_CHECKING

from ._native import InternalError, LimbfuseError
from ._trial import Trial, read_trial, write_trial
from ._estimate import (
    Estimate,
    LimbfuseWarning,
    default_params,
    estimate,
    evaluate,
    inspect,
    methods,
    read_estimate,
)
from ._filter import Filter
from ._montecarlo import montecarlo
from ._workflows import (
    Calibration,
    align,
    calibrate,
    gait_library,
    import_recording,
    mirror,
    repair_time,
    report,
    resample,
    simulate,
    tune,
)

if TYPE_CHECKING:  # pragma: no cover
    from . import cohort as cohort  # (imported on first use: `__getattr__` below)
else:
    # (hidden from type checkers: with it, mypy took a misspelt
    # `limbfuse.estimat` for a module attribute; an audit)
    def __getattr__(name: str) -> ModuleType:
        # `limbfuse.cohort` without importing it with the package, so that
        # `python -m limbfuse.cohort` runs it as a fresh module.
        if name == "cohort":
            import importlib

            return importlib.import_module(".cohort", __name__)
        raise AttributeError(f"module 'limbfuse' has no attribute {name!r}")


#: Every method name, in ``limbfuse methods`` order.
METHODS = tuple(name for name, _ in methods())

__all__ = [
    "METHODS",
    "Calibration",
    "Estimate",
    "Filter",
    "InternalError",
    "LimbfuseError",
    "LimbfuseWarning",
    "Trial",
    "align",
    "calibrate",
    "cohort",
    "default_params",
    "estimate",
    "evaluate",
    "gait_library",
    "import_recording",
    "inspect",
    "methods",
    "mirror",
    "montecarlo",
    "read_estimate",
    "read_trial",
    "repair_time",
    "report",
    "resample",
    "simulate",
    "tune",
    "write_trial",
]
