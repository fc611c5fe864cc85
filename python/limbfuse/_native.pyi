"""Type stubs of the Rust extension `limbfuse._native` (python/src/).

Trials cross as ``(meta items, t, names, arrays, phase_ref cells, source)``
and estimates as ``(header lines, t, names, arrays, phase cells)`` (handed
back with the file's column order, a restart warning and which arrays hold
a NaN, None = not known); arrays are float64 with NaN = missing (the public
classes mask them).
"""

from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]
TrialTuple = Tuple[
    List[Tuple[str, str]], F64, List[str], List[F64], Optional[List[Optional[str]]], Optional[Tuple[str, str]]
]
EstimateArgs = Tuple[List[str], F64, List[str], List[F64], Optional[List[Optional[str]]]]
EstimateTuple = Tuple[
    List[str],
    List[str],
    F64,
    List[str],
    List[F64],
    Optional[List[Optional[str]]],
    Optional[str],
    Optional[List[bool]],
    Optional[str],
]

class LimbfuseError(ValueError): ...
class InternalError(RuntimeError): ...

def methods() -> List[Tuple[str, str]]: ...
def method_details() -> List[Tuple[str, str, str, str]]: ...
def default_params(method: str) -> str: ...
def inspect(
    path: str,
) -> Tuple[
    int,
    Optional[Tuple[float, float]],
    Optional[float],
    Optional[float],
    int,
    Optional[Tuple[float, float]],
    List[Tuple[str, int]],
    List[str],
    List[Tuple[str, str, str]],
    List[str],
    Optional[float],
    Tuple[List[str], Tuple[bool, Optional[bool], Optional[str]]],
]: ...
def read_trial(path: str) -> TrialTuple: ...
def write_trial(path: str, trial: TrialTuple) -> None: ...
def check_channel_names(meta: List[Tuple[str, str]], names: List[str]) -> None: ...
def check_trial(trial: TrialTuple) -> None: ...
def estimate(
    trial: TrialTuple, method: str, params: Any = None, options: Optional[Dict[str, Any]] = None
) -> EstimateTuple: ...
def read_estimate(path: str) -> EstimateTuple: ...
def write_estimate(path: str, estimate: EstimateArgs) -> None: ...
def check_estimate(estimate: EstimateArgs) -> None: ...
def evaluate(
    trial: TrialTuple,
    estimate: EstimateArgs,
    window: Optional[str] = None,
    offset_free: bool = False,
    max_lag: int = 0,
    allow_trial_mismatch: bool = False,
) -> str: ...
def strides(
    estimate: EstimateArgs,
    trial: Optional[TrialTuple] = None,
    allow_trial_mismatch: bool = False,
    window: Optional[str] = None,
) -> Tuple[List[str], List[str], List[Tuple[str, List[float]]]]: ...
def simulate(kind: str, options: Optional[Dict[str, Any]] = None) -> TrialTuple: ...
def align(trial: TrialTuple, options: Optional[Dict[str, Any]] = None) -> Tuple[TrialTuple, List[str]]: ...
def calibrate(trial: TrialTuple, options: Optional[Dict[str, Any]] = None) -> Tuple[str, List[Dict[str, Any]]]: ...
def repair_time(path: str, output: str, out_of_order: str = "drop") -> Dict[str, Any]: ...
def resample(trial: TrialTuple, rate_hz: float, anti_alias: str = "sinc") -> Tuple[TrialTuple, List[str]]: ...
def mirror(trial: TrialTuple, remount_seed: Optional[int] = None) -> Tuple[TrialTuple, List[str]]: ...
def import_recording(path: str, format: str, leg: Optional[str] = None, calibration: Optional[Tuple[str, str]] = None) -> TrialTuple: ...
def tune(
    trial: TrialTuple,
    method: str,
    window: str,
    params: Any = None,
    preset: str = "default",
    validate: Optional[str] = None,
    seed: int = 1,
    budget: int = 400,
    particles: int = 20,
    starts: int = 50,
    length: Optional[float] = None,
) -> Dict[str, Any]: ...
def montecarlo(
    runs: int = 100,
    levels: Union[None, str, Sequence[float]] = None,
    seed: int = 1,
    speed: float = 1.0,
    duration: float = 30.0,
    svg: Optional[str] = None,
    progress: bool = False,
) -> Dict[str, Any]: ...
def gait_library(path: str, speeds: Sequence[float], mass: float = 80.0, leg_length: float = 1.0) -> List[Dict[str, float]]: ...
def report(
    trial: str,
    estimates: List[str],
    path: str,
    buckets: int,
    allow_trial_mismatch: bool,
    command: str,
    window: Optional[str] = None,
    offset_free: bool = False,
    max_lag: int = 0,
) -> int: ...
def _panic_for_test() -> None: ...

class NativeFilter:
    def __init__(
        self,
        method: str,
        channels: List[str],
        meta: List[Tuple[str, str]],
        params: Any = None,
        options: Optional[Dict[str, Any]] = None,
    ) -> None: ...
    @property
    def channels(self) -> List[str]: ...
    @property
    def header(self) -> List[str]: ...
    @property
    def frame_note(self) -> Optional[str]: ...
    def reset(self) -> None: ...
    def step(self, sample: Dict[str, Optional[float]]) -> Dict[str, Any]: ...
    def run(self, t: F64, names: List[str], arrays: List[F64]) -> EstimateTuple: ...
