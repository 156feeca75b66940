"""Type stubs of the native module ``rvlife._rvlife`` (PyO3). A config is loaded once
(:func:`load`: TOML text, origin, base folder) and passed to every command; results are the command line's JSON objects as dicts, lists
of floats as numpy float64 arrays. Bad input raises ValueError naming the key."""

from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

Progress = Optional[Callable[[int, int], None]]

def version() -> str: ...
def commands() -> str: ...
def quantities() -> List[Tuple[str, str, str, str, str, List[str]]]: ...
def example_toml(preset: str = "rv-40e") -> str: ...
def presets() -> List[Tuple[str, str]]: ...
class Loaded:
    """A parsed and validated config."""

def load(text: str, origin: str, base_dir: Optional[str] = None, work_budget_min: float = 10.0) -> Loaded: ...
def toml_from_json(json: str) -> str: ...
def profile(
    cfg: Loaded,
    wear_um: Optional[float],
    hours: Optional[float],
    nominal: bool,
    points_per_tooth: int,
    progress: Progress = None,
) -> Dict[str, Any]: ...
def contact(
    cfg: Loaded,
    crank_deg: float,
    torque_nm: float,
    wear_um: Optional[float],
    hours: Optional[float],
    progress: Progress = None,
) -> Dict[str, Any]: ...
def te(
    cfg: Loaded,
    torque_nm: Optional[float],
    wear_um: Optional[float],
    hours: Optional[float],
    progress: Progress = None,
) -> Dict[str, Any]: ...
def hysteresis(
    cfg: Loaded,
    crank_deg: float,
    levels: int,
    wear_um: Optional[float],
    hours: Optional[float],
    progress: Progress = None,
) -> Dict[str, Any]: ...
def efficiency(
    cfg: Loaded,
    speeds_rpm: Optional[List[float]],
    torques_nm: Optional[List[float]],
    temperatures_c: Optional[List[float]],
    wear_um: Optional[float],
    hours: Optional[float],
    progress: Progress = None,
) -> Dict[str, Any]: ...
def dynamics(
    cfg: Loaded,
    load: Optional[str],
    torque_nm: Optional[float],
    disc: Optional[str],
    wear_um: Optional[float],
    hours: Optional[float],
    pin_forces: bool,
    out: Optional[str],
    force: bool,
    progress: Progress = None,
) -> Dict[str, Any]: ...
def run_study(
    cfg: Loaded,
    out: Optional[str],
    force: bool,
    progress: Progress = None,
) -> Dict[str, Any]: ...
def montecarlo(
    cfg: Loaded,
    samples: int,
    seed: int,
    shard: Optional[str],
    full_wear: bool,
    samples_per_mesh_cycle: int,
    out: Optional[str],
    force: bool,
    progress: Progress = None,
    shared_wear: Optional[str] = None,
    threads: Optional[int] = None,
) -> Dict[str, str]: ...
def merge(dirs: List[str], out: str, force: bool) -> None: ...
def nominal_wear(cfg: Loaded, threads: Optional[int] = None) -> str: ...
def config_set(text: str, origin: str, edits: str) -> str: ...
def config_merge(text: str, origin: str, patch: str) -> str: ...
def config_to_dict(text: str, origin: str) -> Dict[str, Any]: ...
def accuracy_life(cfg: Loaded, progress: Progress = None) -> Dict[str, Any]: ...
def calibrate_target(cfg: Loaded, target_wear_um: float) -> Dict[str, Any]: ...
def calibrate_measured(
    cfg: Loaded,
    csv: str,
    name: str,
    fit_running_in: bool,
    out: Optional[str],
    force: bool,
    progress: Progress = None,
) -> Dict[str, Any]: ...
def calibrate_structure(cfg: Loaded, csv: Optional[str], name: str, catalogue: Optional[float]) -> Dict[str, Any]: ...
def is_hysteresis_curve(csv: str) -> bool: ...
def sweep_designs(text: str, origin: str, base_dir: Optional[str], vary: str, work_budget_min: float) -> List[str]: ...
def optimize(
    problem: OptimizeProblem,
    out: Optional[str],
    force: bool,
    progress: Progress = None,
    batch: Optional[Callable[[List[Tuple[List[float], int, str]]], List[str]]] = None,
) -> Dict[str, Any]: ...

class OptimizeProblem:
    """A design search's problem on a cluster's worker, built and validated once."""

    def __init__(
        self,
        text: str,
        origin: str,
        base_dir: Optional[str],
        work_budget_min: float,
        vary: Sequence[str],
        objective: str,
        constraints: Sequence[str],
        evaluations: int,
        seed: int,
    ) -> None: ...
    def evaluate(self, unit: List[float], index: int, phase: str) -> str: ...
