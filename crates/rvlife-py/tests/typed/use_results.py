"""A script as a notebook user writes it, checked by ``mypy --strict`` (test_typing.py): every
attribute it reads must be declared with its type."""

from typing import List, Optional

import numpy as np
import numpy.typing as npt
import pandas as pd

import rvlife


def lost_motion_growth(cfg: rvlife.Config) -> float:
    study: rvlife.StudyResult = rvlife.run_study(cfg)
    lm: npt.NDArray[np.float64] = study.lost_motion_arcmin
    verdict: str = study.verdict
    assert verdict
    return float(lm[-1] - lm[0])


def te_summary(cfg: Optional[rvlife.Config] = None) -> str:
    r = rvlife.te(cfg, wear_um=5.0, torque_nm=412.0)
    mean: float = r.te_mean_arcmin
    lm: float = r.lost_motion_arcmin
    loaded: Optional[float] = r.loaded_te_mean_arcmin
    curve: npt.NDArray[np.float64] = r.te_arcmin
    frame: pd.DataFrame = r.to_pandas()
    return f"{mean:.4f} {lm:.4f} {loaded} {curve.size} {len(frame)}"


def life(cfg: rvlife.Config) -> Optional[float]:
    a = rvlife.accuracy_life(cfg)
    hours: Optional[float] = a.accuracy_life_h
    by: Optional[str] = a.limited_by
    assert by is None or isinstance(by, str)
    return hours


def design_grid() -> pd.DataFrame:
    base = rvlife.example().replace({"dynamics.enabled": False, "fem.enabled": False})
    configs: List[rvlife.Config] = rvlife.grid({"cycloid.eccentricity_mm": [1.25, 1.3]}, base)
    table: pd.DataFrame = rvlife.sweep(configs)
    return table


def monte_carlo(cfg: rvlife.Config) -> int:
    mc: rvlife.MonteCarloResult = rvlife.montecarlo(cfg, samples=4)
    samples: pd.DataFrame = mc.samples
    return len(samples)


def calibration(cfg: rvlife.Config, data: pd.DataFrame) -> float:
    fit: rvlife.ArchardFit = rvlife.calibrate(cfg, target_wear_um=20.0)
    k: float = fit.archard_coefficient_mm3_per_n_m
    cal: rvlife.Calibration = rvlife.calibrate(cfg, measured=data)
    points: int = cal.points
    structure: rvlife.StructureFit = rvlife.calibrate_structure(cfg, catalogue_stiffness_nm_per_arcmin=108.0)
    stiffness: float = structure.fitted_stiffness_nm_per_arcmin
    return k * points + stiffness


def edit(cfg: rvlife.Config) -> rvlife.Config:
    c = cfg.replace({"cycloid.eccentricity_mm": 1.25})
    d = c.to_dict()
    text: str = c.to_toml()
    assert text and isinstance(d, dict)
    return rvlife.Config.from_dict({"cycloid": {"pins": 40}}, base=c)
