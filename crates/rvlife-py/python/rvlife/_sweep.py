"""Design sweeps, the design search and distributed runs: :func:`grid` builds the product of
configs, :func:`sweep` runs their studies (in this process, or on a ``dask.distributed``
client) into one tidy DataFrame, or runs a :class:`MonteCarlo` plan in shards that share one
nominal wear history; :func:`optimize` searches the keys' ranges for the longest accuracy life
(``rvlife optimize``)."""

from __future__ import annotations

import io
import math
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union, overload

import pandas as pd

from . import _rvlife
from ._commands import Progress, _cfg, _mc_result, _out, _study_result, merge, run_study
from ._config import Config, PathLike, _json, example
from ._results import MonteCarloResult, StudyResult, stage_table


def grid(axes: Mapping[str, Sequence[Any]], base: Optional[Config] = None) -> List[Config]:
    """The product of the values of dotted keys over ``base`` (default: the built-in
    example), the last key varying fastest (``rvlife sweep --vary``'s order):
    ``grid({"cycloid.eccentricity_mm": [1.25, 1.3], "cycloid.modification.equidistant_mm":
    [0.010, 0.012]})`` is four configs. Every design is validated and the whole sweep's
    estimated work checked against ``base``'s work budget before any study runs;
    ``ValueError`` names the key, the value and the design."""
    b = base if base is not None else example()
    keys = list(axes)
    values = [list(axes[k]) for k in keys]
    if any(len(v) == 0 for v in values):
        raise ValueError(f"invalid grid: every key needs at least one value ({[k for k, v in zip(keys, values) if not v]})")
    spec = _json([[k, v] for k, v in zip(keys, values)])
    texts = _rvlife.sweep_designs(b.toml, b.origin, b.base_dir, spec, b.work_budget_min)
    configs = []
    for i, text in enumerate(texts):
        rest = i
        chosen: Dict[str, Any] = {}
        for k, v in reversed(list(zip(keys, values))):
            chosen[k] = v[rest % len(v)]
            rest //= len(v)
        changes = dict(b.changes)
        changes.update({k: chosen[k] for k in keys})
        configs.append(Config(text, b.origin, b.base_dir, work_budget_min=b.work_budget_min, changes=changes))
    return configs


@dataclass
class MonteCarlo:
    """A Monte Carlo plan for :func:`sweep`: ``samples`` reducers drawn from the config's
    ``[tolerances]`` with ``seed`` (as ``rvlife montecarlo``)."""

    config: Optional[Config]
    samples: int
    seed: int = 1
    full_wear: bool = False
    samples_per_mesh_cycle: int = 4


def _study_task(config: tuple, out: Optional[str], force: bool) -> Dict[str, Any]:
    """One study, on a worker (writing ``out`` when given: workers must see that folder)."""
    text, origin, base_dir, budget = config
    return _rvlife.run_study(_rvlife.load(text, origin, base_dir, budget), out, force, None)


def _shard_task(config: tuple, mc: tuple, shard: str, wear: Optional[str]) -> Dict[str, str]:
    """One shard of a Monte Carlo run, on a worker, on the shared nominal wear and one core."""
    text, origin, base_dir, budget = config
    samples, seed, full_wear, per_cycle = mc
    loaded = _rvlife.load(text, origin, base_dir, budget)
    return _rvlife.montecarlo(loaded, samples, seed, shard, full_wear, per_cycle, None, False, None, wear, 1)


def _row_frame(k: int, config: Config, keys: List[str], study: Optional[StudyResult], status: str) -> pd.DataFrame:
    """One design's rows of the tidy table (``sweep.csv``'s columns)."""
    life = (study.accuracy_life or {}) if study is not None else {}
    lead: Dict[str, Any] = {"design": k}
    for key in keys:
        lead[key] = config.changes.get(key)
    lead["status"] = status
    hours = life.get("accuracy_life_h")
    lead["accuracy_life_h"] = math.nan if hours is None else hours
    lead["limited_by"] = life.get("limited_by")
    # A failed design: one row, its quantities NaN.
    stages = stage_table(study.stages if study is not None else [{}])
    front = pd.DataFrame([lead] * len(stages))
    return pd.concat([front.reset_index(drop=True), stages.reset_index(drop=True)], axis=1)


@overload
def sweep(configs_or_samples: MonteCarlo, client: Any = ..., *, out: Optional[PathLike] = ..., force: bool = ..., tasks: Optional[int] = ..., progress: Optional[Progress] = ...) -> MonteCarloResult: ...


@overload
def sweep(configs_or_samples: Sequence[Config], client: Any = ..., *, out: Optional[PathLike] = ..., force: bool = ..., tasks: Optional[int] = ..., progress: Optional[Progress] = ...) -> pd.DataFrame: ...


def sweep(
    configs_or_samples: Union[MonteCarlo, Sequence[Config]],
    client: Any = None,
    *,
    out: Optional[PathLike] = None,
    force: bool = False,
    tasks: Optional[int] = None,
    progress: Optional[Progress] = None,
) -> Union[MonteCarloResult, pd.DataFrame]:
    """Runs a design sweep or a Monte Carlo plan, in this process (``client=None``) or on a
    ``dask.distributed`` client (a ``LocalCluster``'s, or e.g. dask-jobqueue's
    ``SLURMCluster``'s).

    - A list of :class:`Config` (:func:`grid`) runs one accuracy-life study each and returns
      one tidy DataFrame, one row per config and stage: ``design``, the keys the configs
      change (``Config.changes``) as columns, ``status``, ``accuracy_life_h``, ``limited_by``
      and the columns of ``stages.csv``: the table ``rvlife sweep`` writes as ``sweep.csv``. A
      study that fails gives one row with its reason in ``status``. With ``out``, study ``k``
      writes ``out/design_<k>`` (the files of ``rvlife run``).
    - A :class:`MonteCarlo` plan computes the nominal reducer's wear history once, here, sends
      it to the workers and runs ``tasks`` shards on it (default: four per worker thread, at
      most one per sample), each on one core; the shards merge into exactly the serial run's
      records and ``out`` gets the files of ``rvlife montecarlo``.
    """
    if isinstance(configs_or_samples, MonteCarlo):
        return _montecarlo_sweep(configs_or_samples, client, out, force, tasks, progress)
    configs = [_cfg(c) for c in configs_or_samples]
    _out(out, force)
    keys: List[str] = []
    for c in configs:
        keys.extend(k for k in c.changes if k not in keys)
    outs: List[Optional[str]] = [None] * len(configs)
    if out is not None:
        root = Path(out)
        root.mkdir(parents=True, exist_ok=True)
        outs = [str(root / f"design_{k}") for k in range(len(configs))]
    results: List[Union[StudyResult, str]] = []
    if client is None:
        for k, (c, o) in enumerate(zip(configs, outs)):
            try:
                results.append(run_study(c, out=o, force=force))
            except RuntimeError as e:
                results.append(f"failed: {e}")
            if progress is not None:
                progress(k + 1, len(configs))
    else:
        from dask.distributed import as_completed

        futures = [client.submit(_study_task, c._text(), o, force, pure=False) for c, o in zip(configs, outs)]
        index = {f.key: k for k, f in enumerate(futures)}
        slots: List[Union[StudyResult, str]] = [""] * len(configs)
        for n, f in enumerate(as_completed(futures), start=1):
            k = index[f.key]
            try:
                slots[k] = _study_result(f.result(), outs[k])
            except RuntimeError as e:
                slots[k] = f"failed: {e}"
            if progress is not None:
                progress(n, len(configs))
        results = slots
    frames = [
        _row_frame(k, c, keys, r if isinstance(r, StudyResult) else None, "ok" if isinstance(r, StudyResult) else r)
        for k, (c, r) in enumerate(zip(configs, results))
    ]
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame()


def _montecarlo_sweep(
    mc: MonteCarlo,
    client: Any,
    out: Optional[PathLike],
    force: bool,
    tasks: Optional[int],
    progress: Optional[Progress],
) -> MonteCarloResult:
    c = _cfg(mc.config)
    o = _out(out, force)
    if client is None:
        data = _rvlife.montecarlo(c._loaded, mc.samples, mc.seed, None, mc.full_wear, mc.samples_per_mesh_cycle, o, force, progress)
        return _mc_result(data, out)
    from dask.distributed import as_completed

    threads = sum(client.nthreads().values()) or 1
    n = tasks if tasks is not None else 4 * threads
    n = max(1, min(int(n), mc.samples))
    # The nominal wear once, here (all cores), then to every worker.
    wear = None if mc.full_wear else _rvlife.nominal_wear(c._loaded)
    wear_f = None if wear is None else client.scatter(wear, broadcast=True)
    plan = (mc.samples, mc.seed, mc.full_wear, mc.samples_per_mesh_cycle)
    futures = [client.submit(_shard_task, c._text(), plan, f"{i}/{n}", wear_f, pure=False) for i in range(1, n + 1)]
    done = 0
    for f in as_completed(futures):
        done += 1
        if progress is not None:
            progress(done, n)
    parts = client.gather(futures)
    with tempfile.TemporaryDirectory(prefix="rvlife-sweep-") as tmp:
        dirs = []
        for i, part in enumerate(parts, start=1):
            d = Path(tmp) / f"shard_{i}"
            d.mkdir()
            (d / "samples.csv").write_text(part["samples_csv"])
            (d / "stages.csv").write_text(part["stages_csv"])
            (d / "shard.json").write_text(part["shard_json"])
            dirs.append(str(d))
        r = merge(dirs, o if o is not None else Path(tmp) / "merged", force=force)
        if o is None:
            r.out = None  # the merged files were in the temporary folder
        return r


__all__ = ["grid", "sweep", "MonteCarlo"]


@dataclass
class OptimizeResult:
    """What :func:`optimize` found: ``candidates`` (every candidate, the columns of
    ``candidates.csv``), ``pareto`` (the front's candidates, ``pareto.csv``), ``best`` and
    ``start`` (the best feasible and the base design's rows, ``None`` if there is none),
    ``optimum`` (the best design's config: the base with the varied keys set), ``stopped`` and
    ``out`` (the results directory, if written)."""

    candidates: pd.DataFrame
    pareto: pd.DataFrame
    best: Optional["pd.Series[Any]"]
    start: Optional["pd.Series[Any]"]
    optimum: Optional[Config]
    stopped: bool
    out: Optional[Path]


_PROBLEMS: Dict[tuple, Any] = {}


def _candidate_task(problem: tuple, unit: List[float], index: int, phase: str) -> str:
    """One candidate of a design search on a worker: the problem built once per worker
    process (its validation is not repeated for each candidate)."""
    p = _PROBLEMS.get(problem)
    if p is None:
        if len(_PROBLEMS) >= 4:
            _PROBLEMS.clear()  # a long-lived worker keeps only the last few searches' problems
        p = _PROBLEMS[problem] = _rvlife.OptimizeProblem(*problem)
    return str(p.evaluate(unit, index, phase))


def optimize(
    vary: Mapping[str, Tuple[float, float]],
    objective: str = "life",
    *,
    constraints: Sequence[str] = (),
    evaluations: int = 150,
    seed: int = 1,
    base: Optional[Config] = None,
    out: Optional[PathLike] = None,
    force: bool = False,
    progress: Optional[Progress] = None,
    client: Any = None,
) -> OptimizeResult:
    """The design search (``rvlife optimize``, docs/model.md section 19): the values of the
    dotted keys of ``vary`` (``{"cycloid.modification.equidistant_mm": (0.005, 0.03)}``), each
    within its range, that keep ``base`` (default: the built-in example) in spec longest
    (``objective="life"``, or ``"b10"``), or the Pareto front of several goals
    (``"life,lost_motion_arcmin"``), under ``constraints`` (``"lost_motion_arcmin<=0.8"``),
    in at most ``evaluations`` studies, reproducible with ``seed``. Runs in this process (each
    study on every core), or with a ``dask.distributed`` ``client`` sends the candidates the
    search asks for together (its Latin hypercube, each generation of NSGA-II) to the workers
    at once, the others one at a time: the same candidates either way. The ranges, goals,
    constraints and the whole search's work are
    checked before any study; ``ValueError`` names the key or the argument. With ``out``, also
    writes the command line's files (and its report's follow-up studies)."""
    b = base if base is not None else example()
    specs = []
    for key, rng in vary.items():
        lo, hi = rng
        specs.append(f"{key}={lo!r}:{hi!r}")
    args = (b.toml, b.origin, None if b.base_dir is None else str(b.base_dir), b.work_budget_min, tuple(specs), objective, tuple(constraints), int(evaluations), int(seed))
    problem = _rvlife.OptimizeProblem(*args)
    o = _out(out, force)
    batch: Optional[Callable[[List[Tuple[List[float], int, str]]], List[str]]] = None
    if client is not None:

        def on_cluster(jobs: List[Tuple[List[float], int, str]]) -> List[str]:
            futures = [client.submit(_candidate_task, args, list(u), i, ph, pure=False) for u, i, ph in jobs]
            return [str(t) for t in client.gather(futures)]

        batch = on_cluster

    r = _rvlife.optimize(problem, o, force, progress, batch)
    candidates = pd.read_csv(io.StringIO(r["candidates_csv"]))
    pareto = pd.read_csv(io.StringIO(r["pareto_csv"]))
    best = None if r["best"] is None else candidates.iloc[int(r["best"])]
    start = None if r["start"] is None else candidates.iloc[int(r["start"])]
    optimum = None
    if r["optimum_toml"] is not None and best is not None:
        changes = dict(b.changes)
        changes.update({k: best[k].item() if hasattr(best[k], "item") else best[k] for k in vary})
        optimum = Config(r["optimum_toml"], b.origin, b.base_dir, work_budget_min=b.work_budget_min, changes=changes)
    return OptimizeResult(candidates, pareto, best, start, optimum, bool(r["stopped"]), None if o is None else Path(o))
