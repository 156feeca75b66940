"""The command line's commands as functions: the same Rust calls, the same validation, the same
pairs of arguments refused, messages naming the keyword argument."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Callable, Dict, Optional, Sequence, Union, overload

import pandas as pd

from . import _rvlife
from ._config import Config, PathLike, example
from ._results import (
    AccuracyLifeResult,
    ArchardFit,
    Calibration,
    ContactResult,
    DynamicsResult,
    EfficiencyResult,
    HysteresisResult,
    MonteCarloResult,
    ProfileResult,
    StructureFit,
    StudyResult,
    TeResult,
)

#: ``progress(done, total)``: called as work completes, ``done`` never decreasing.
Progress = Callable[[int, int], None]


def _cfg(config: Optional[Config]) -> Config:
    if config is None:
        return example()
    if not isinstance(config, Config):
        raise TypeError(f"config must be an rvlife.Config or None, not {type(config).__name__}")
    return config


def _whole(name: str, v: Any, least: int = 0) -> None:
    """Refuses ``v`` unless it is a whole number of at least ``least`` (as the command line
    refuses ``--samples -1``), naming the keyword ``name``."""
    if isinstance(v, bool) or not isinstance(v, int) or v < least:
        raise ValueError(f"invalid {name} = {v!r}: must be a whole number, {least} or more")


def _out(out: Optional[PathLike], force: bool) -> Optional[str]:
    """The results directory as the native calls take it; ``force`` needs one."""
    if force and out is None:
        raise ValueError("invalid force = True: replaces the results directory out; give out too")
    return None if out is None else os.fspath(out)


def profile(
    config: Optional[Config] = None,
    *,
    wear_um: Optional[float] = None,
    hours: Optional[float] = None,
    nominal: bool = False,
    points_per_tooth: int = 0,
    progress: Optional[Progress] = None,
) -> ProfileResult:
    """The disc profile: unworn, worn uniformly by ``wear_um`` (um), or by the config's wear
    model after ``hours`` (h; not both); ``nominal`` drops the modifications.
    ``points_per_tooth`` 0 takes the export's default."""
    c = _cfg(config)
    return ProfileResult(_rvlife.profile(c._loaded, wear_um, hours, nominal, points_per_tooth, progress))


def contact(
    config: Optional[Config] = None,
    *,
    crank_deg: float,
    torque_nm: float,
    wear_um: Optional[float] = None,
    hours: Optional[float] = None,
    progress: Optional[Progress] = None,
) -> ContactResult:
    """Static equilibrium of the reducer at ``crank_deg`` (deg) under the output torque
    ``torque_nm`` (N m), input locked (``rvlife contact``)."""
    c = _cfg(config)
    return ContactResult(_rvlife.contact(c._loaded, crank_deg, torque_nm, wear_um, hours, progress))


def te(
    config: Optional[Config] = None,
    *,
    torque_nm: Optional[float] = None,
    wear_um: Optional[float] = None,
    hours: Optional[float] = None,
    progress: Optional[Progress] = None,
) -> TeResult:
    """STE, backlash, lost motion and torsional stiffness over a mesh cycle, STE over an output
    revolution; with ``torque_nm`` (N m) also the loaded TE (``rvlife te``)."""
    c = _cfg(config)
    return TeResult(_rvlife.te(c._loaded, torque_nm, wear_um, hours, progress))


def hysteresis(
    config: Optional[Config] = None,
    *,
    crank_deg: float = 0.0,
    levels: int = 10,
    wear_um: Optional[float] = None,
    hours: Optional[float] = None,
    progress: Optional[Progress] = None,
) -> HysteresisResult:
    """The hysteresis curve (output torque 0 -> +rated -> -rated -> +rated in ``levels`` steps
    per quarter, input locked), mean over a mesh cycle and at ``crank_deg``."""
    c = _cfg(config)
    _whole("levels", levels)
    return HysteresisResult(_rvlife.hysteresis(c._loaded, crank_deg, levels, wear_um, hours, progress))


def efficiency(
    config: Optional[Config] = None,
    *,
    speeds_rpm: Optional[Sequence[float]] = None,
    torques_nm: Optional[Sequence[float]] = None,
    temperatures_c: Optional[Sequence[float]] = None,
    wear_um: Optional[float] = None,
    hours: Optional[float] = None,
    progress: Optional[Progress] = None,
) -> EfficiencyResult:
    """The power losses and efficiency (``rvlife efficiency``) at every output speed (rpm),
    output torque (N m) and oil temperature (deg C) given (defaults: 5-50 rpm, a quarter to all
    of the rated torque, ``[lubrication] temperature_c``), split by contact kind, and at the
    rated point; ``to_pandas()`` gives the map, one row per point."""
    c = _cfg(config)
    lists = [None if v is None else [float(x) for x in v] for v in (speeds_rpm, torques_nm, temperatures_c)]
    return EfficiencyResult(
        _rvlife.efficiency(c._loaded, lists[0], lists[1], lists[2], wear_um, hours, progress)
    )


def dynamics(
    config: Optional[Config] = None,
    *,
    load: Optional[str] = None,
    torque_nm: Optional[float] = None,
    disc: Optional[str] = None,
    wear_um: Optional[float] = None,
    hours: Optional[float] = None,
    pin_forces: bool = False,
    out: Optional[PathLike] = None,
    force: bool = False,
    progress: Optional[Progress] = None,
) -> DynamicsResult:
    """Multibody simulation of the whole reducer (``rvlife dynamics``): ``load`` overrides
    ``[dynamics.load] kind`` (``none``, ``constant``, ``sinusoidal``, ``table``), ``torque_nm``
    a constant load's torque, ``disc`` the disc model (``rigid`` or ``flexible``); ``out`` also
    writes the results directory."""
    c = _cfg(config)
    o = _out(out, force)
    return DynamicsResult(
        _rvlife.dynamics(c._loaded, load, torque_nm, disc, wear_um, hours, pin_forces, o, force, progress)
    )


def run_study(
    config: Optional[Config] = None,
    *,
    out: Optional[PathLike] = None,
    force: bool = False,
    progress: Optional[Progress] = None,
) -> StudyResult:
    """The accuracy-life study (``rvlife run``); ``out`` also writes its results directory
    (atomically; ``force`` replaces an existing one)."""
    c = _cfg(config)
    o = _out(out, force)
    return _study_result(_rvlife.run_study(c._loaded, o, force, progress), o)


def _study_result(data: Dict[str, Any], out: Optional[str]) -> StudyResult:
    """A study's result from the native call's ``summary.json`` with its ``verdict``."""
    verdict = data.pop("verdict", "")
    return StudyResult(data, verdict, None if out is None else Path(out))


def accuracy_life(config: Optional[Config] = None, *, progress: Optional[Progress] = None) -> AccuracyLifeResult:
    """The accuracy life against the config's spec (``[life]``): the study without its dynamic
    and FE analyses, which do not enter the life (the same hours as :func:`run_study`'s
    ``accuracy_life``, faster)."""
    c = _cfg(config)
    return AccuracyLifeResult(_rvlife.accuracy_life(c._loaded, progress))


def _measured_csv(measured: Union[PathLike, pd.DataFrame]) -> tuple:
    """``(text, name)`` of measurements given as a DataFrame or a CSV file."""
    if isinstance(measured, pd.DataFrame):
        return measured.to_csv(index=False), "measured (a DataFrame)"
    p = Path(measured)
    try:
        return p.read_text(), str(p)
    except OSError as e:
        raise ValueError(f"invalid measured = {str(p)!r}: cannot read the file: {e}") from e


@overload
def calibrate(
    config: Optional[Config] = ...,
    *,
    target_wear_um: Optional[float] = ...,
    measured: None = ...,
    fit_running_in: bool = ...,
    out: None = ...,
    force: bool = ...,
    progress: Optional[Progress] = ...,
) -> ArchardFit: ...


@overload
def calibrate(
    config: Optional[Config] = ...,
    *,
    target_wear_um: None = ...,
    measured: Union[PathLike, pd.DataFrame],
    fit_running_in: bool = ...,
    out: Optional[PathLike] = ...,
    force: bool = ...,
    progress: Optional[Progress] = ...,
) -> Calibration: ...


def calibrate(
    config: Optional[Config] = None,
    *,
    target_wear_um: Optional[float] = None,
    measured: Optional[Union[PathLike, pd.DataFrame]] = None,
    fit_running_in: bool = False,
    out: Optional[PathLike] = None,
    force: bool = False,
    progress: Optional[Progress] = None,
) -> Union[ArchardFit, Calibration]:
    """``rvlife calibrate``: the Archard coefficient that gives ``target_wear_um`` (um,
    default 60) of largest wear at the last stage (:class:`ArchardFit`), or, with
    ``measured`` (a DataFrame or a CSV file: ``hours`` and one or more of
    ``lost_motion_arcmin``, ``backlash_arcmin``, ``angular_te_arcmin``, ``max_wear_um``), the
    coefficient fitted to the measurements with its 95 % interval (:class:`Calibration`);
    ``fit_running_in`` also fits a running-in play, ``out`` writes the fit's results
    directory. The command line's pairs are refused: ``target_wear_um`` with ``measured``,
    ``fit_running_in`` or ``out`` without it, ``force`` without ``out``. A hysteresis curve
    (``torque_nm``, ``twist_arcmin``) is :func:`calibrate_structure`'s."""
    c = _cfg(config)
    if measured is None:
        for name, given in (("fit_running_in", fit_running_in), ("out", out is not None), ("force", force)):
            if given:
                raise ValueError(f"invalid {name} = {True if given is True else out!r}: needs measured (the fit to measurements)")
        return ArchardFit(_rvlife.calibrate_target(c._loaded, 60.0 if target_wear_um is None else target_wear_um))
    if target_wear_um is not None:
        raise ValueError(
            f"invalid target_wear_um = {target_wear_um!r}: give either target_wear_um (aim at a wear depth) "
            "or measured (fit to measurements), not both"
        )
    o = _out(out, force)
    text, name = _measured_csv(measured)
    if _rvlife.is_hysteresis_curve(text):
        raise ValueError(
            f"invalid measured = {name!r}: a hysteresis curve (torque_nm, twist_arcmin) fits the "
            "structure compliance: use rvlife.calibrate_structure(config, curve=...)"
        )
    r = Calibration(_rvlife.calibrate_measured(c._loaded, text, name, fit_running_in, o, force, progress))
    r.out = None if out is None else Path(out)
    return r


def calibrate_structure(
    config: Optional[Config] = None,
    *,
    curve: Optional[Union[PathLike, pd.DataFrame]] = None,
    catalogue_stiffness_nm_per_arcmin: Optional[float] = None,
) -> StructureFit:
    """``rvlife calibrate --measured CURVE`` or ``--catalogue-stiffness-nm-per-arcmin``: the
    structure compliance fitted to a measured hysteresis curve (``curve``, a DataFrame or a CSV
    file with ``torque_nm`` and ``twist_arcmin`` in the bench's order) with its 95 % interval,
    or to a catalogue ``b/a`` (N m/arcmin); exactly one of the two. The result's
    ``calibrated`` is the config with the fitted compliance set (the command line's
    ``calibrated.toml``)."""
    c = _cfg(config)
    if (curve is None) == (catalogue_stiffness_nm_per_arcmin is None):
        raise ValueError(
            "invalid curve / catalogue_stiffness_nm_per_arcmin: give exactly one (a measured "
            "hysteresis curve or a catalogue stiffness)"
        )
    text, name = (None, "catalogue") if curve is None else _measured_csv(curve)
    fit = StructureFit(_rvlife.calibrate_structure(c._loaded, text, name, catalogue_stiffness_nm_per_arcmin))
    value = round(fit.compliance_arcmin_per_knm["value"] * 1e4) / 1e4
    fit.calibrated = c.replace({"reducer.structure.compliance_arcmin_per_knm": value})
    return fit


def _mc_result(data: Dict[str, str], out: Optional[PathLike]) -> MonteCarloResult:
    o = None if out is None else Path(out)
    summary = None
    if o is not None and (o / "summary.json").is_file():
        summary = json.loads((o / "summary.json").read_text())
    return MonteCarloResult(data["samples_csv"], data["stages_csv"], summary, o)


def montecarlo(
    config: Optional[Config] = None,
    *,
    samples: int = 100,
    seed: int = 1,
    shard: Optional[str] = None,
    full_wear: bool = False,
    samples_per_mesh_cycle: int = 4,
    out: Optional[PathLike] = None,
    force: bool = False,
    progress: Optional[Progress] = None,
    threads: Optional[int] = None,
) -> MonteCarloResult:
    """Monte Carlo over ``[tolerances]`` (``rvlife montecarlo``): ``samples`` sampled reducers
    of ``seed``, or the shard ``"I/N"`` of them; ``out`` writes the command line's files (a
    shard's for :func:`merge`); ``threads`` the threads it runs on (default: one per core;
    the records do not depend on it)."""
    c = _cfg(config)
    for name, v in (("samples", samples), ("seed", seed), ("samples_per_mesh_cycle", samples_per_mesh_cycle)):
        _whole(name, v)
    o = _out(out, force)
    if threads is not None:
        _whole("threads", threads, least=1)
    data = _rvlife.montecarlo(
        c._loaded, samples, seed, shard, full_wear, samples_per_mesh_cycle, o, force, progress, None, threads
    )
    return _mc_result(data, out)


def merge(shards: Sequence[PathLike], out: PathLike, *, force: bool = False) -> MonteCarloResult:
    """``rvlife merge``: the shards' results directories (``montecarlo(shard="I/N",
    out=...)``) combined into exactly the files the unsharded run writes, in ``out``."""
    if isinstance(shards, (str, os.PathLike)):
        raise TypeError("shards must be a list of results directories")
    _rvlife.merge([os.fspath(s) for s in shards], os.fspath(out), force)
    o = Path(out)
    return MonteCarloResult((o / "samples.csv").read_text(), (o / "stages.csv").read_text(), json.loads((o / "summary.json").read_text()), o)


def tqdm_progress(bar: Any) -> Progress:
    """A ``progress(done, total)`` callback that moves a tqdm bar forward only, by
    ``bar.update`` (so its rate and remaining time are tqdm's own):
    ``with tqdm() as bar: run_study(cfg, progress=tqdm_progress(bar))``."""

    def update(done: int, total: int) -> None:
        if bar.total != total:
            bar.total = total
            bar.refresh()
        step = done - bar.n
        if step > 0:
            bar.update(step)

    return update

