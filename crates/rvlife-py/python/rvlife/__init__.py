"""rvlife: accuracy-life prediction of RV reducers and cycloid drives, from Python.

Every command of the ``rvlife`` command line is a function here, running the same Rust code
with the same validation: ``profile``, ``contact``, ``te``, ``hysteresis``, ``dynamics``,
``run_study`` and ``montecarlo`` take a :class:`Config` (or ``None``: the built-in example) and
return a typed result whose fields are the keys of the command's JSON output (``rvlife <command>
--json``; ``summary.json`` for a study), numeric series as numpy ``float64`` arrays. Units are
in the names: ``_mm``, ``_um``, ``_deg``, ``_arcmin``, ``_nm`` (newton metres), ``_n``,
``_mpa``, ``_h``, ``_s``.

Bad input raises ``ValueError`` with the command line's message, which names the key (or the
keyword argument), the value and the allowed range. Solves release the GIL; ``progress`` is a
callable ``progress(done, total)`` (e.g. a tqdm bar's update, see :func:`tqdm_progress`).

:func:`sweep` maps studies or Monte Carlo samples over a ``dask.distributed`` client.
"""

from __future__ import annotations

import functools
import json
import math
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Union

import numpy as np

from . import _rvlife

__version__: str = _rvlife.version()

Progress = Callable[[int, int], None]
PathLike = Union[str, "os.PathLike[str]"]

__all__ = [
    "Config",
    "Result",
    "ProfileResult",
    "ContactResult",
    "TeResult",
    "HysteresisResult",
    "DynamicsResult",
    "StudyResult",
    "Quantity",
    "quantities",
    "MonteCarloResult",
    "MonteCarlo",
    "example",
    "presets",
    "profile",
    "contact",
    "te",
    "hysteresis",
    "dynamics",
    "run_study",
    "montecarlo",
    "sweep",
    "tqdm_progress",
]


class Config:
    """A reducer, its tolerances and its duty: the TOML config of the command line.

    Build one with :meth:`from_file`, :meth:`from_toml`, :meth:`from_dict` or :func:`example`.
    It is validated on construction exactly as ``rvlife`` validates a file (``ValueError``
    naming the key). ``toml`` is its text, ``origin`` the name errors give it, ``base_dir`` the
    folder relative paths in it (a measured profile) start from.
    """

    def __init__(self, toml: str, origin: str = "<string>", base_dir: Optional[PathLike] = None):
        self.toml: str = toml
        self.origin: str = origin
        self.base_dir: Optional[str] = None if base_dir is None else os.fspath(base_dir)
        # Parsed and validated once; every call reuses it.
        self._loaded = _rvlife.load(self.toml, self.origin, self.base_dir)

    @classmethod
    def from_file(cls, path: PathLike) -> "Config":
        """The config file at ``path`` (relative paths in it start from its folder)."""
        p = Path(path)
        try:
            text = p.read_text()
        except OSError as e:
            raise ValueError(f"config {p}: cannot read the file: {e}") from e
        return cls(text, str(p), p.parent)

    @classmethod
    def from_toml(cls, text: str, origin: str = "<string>") -> "Config":
        """A config from TOML text."""
        return cls(text, origin)

    @classmethod
    def from_dict(cls, sections: Dict[str, Any], origin: str = "<dict>") -> "Config":
        """A config from a dict of sections, as the TOML file would hold them
        (``{"reducer": {"rated_torque_nm": 412.0}, ...}``)."""
        return cls(_rvlife.toml_from_json(json.dumps(sections)), origin)

    def _args(self) -> tuple:
        return (self._loaded,)

    def _text(self) -> tuple:
        """What rebuilds the config elsewhere (a Dask worker): text, origin, folder."""
        return (self.toml, self.origin, self.base_dir)

    def __getstate__(self) -> tuple:
        return self._text()

    def __setstate__(self, state: tuple) -> None:
        self.__init__(*state)

    def __repr__(self) -> str:
        return f"Config(origin={self.origin!r}, {len(self.toml)} characters of TOML)"


@functools.lru_cache(maxsize=None)
def example(preset: str = "rv-40e") -> Config:
    """A built-in config (``rvlife example --preset``): ``rv-40e`` (the default, the built-in
    example), ``paper`` (the paper's reducer as printed), ``rv-20e``, ``rv-80e``,
    ``single-stage``; :func:`presets` lists them."""
    return Config(_rvlife.example_toml(preset), f"<built-in {preset}>")


def presets() -> List[tuple]:
    """``(name, summary)`` of every built-in config."""
    return list(_rvlife.presets())


def _cfg(config: Optional[Config]) -> Config:
    if config is None:
        return example()
    if not isinstance(config, Config):
        raise TypeError(f"config must be an rvlife.Config or None, not {type(config).__name__}")
    return config


class Result:
    """A command's result: every key of its JSON output as an attribute (and by ``[key]``),
    numeric series as numpy arrays. ``data`` is the whole object; :meth:`to_dict` gives it back
    with arrays as lists (the command line's JSON)."""

    def __init__(self, data: Dict[str, Any]):
        self.data: Dict[str, Any] = data

    def __getattr__(self, name: str) -> Any:
        try:
            return self.__dict__["data"][name]
        except KeyError:
            raise AttributeError(name) from None

    def __getitem__(self, key: str) -> Any:
        return self.data[key]

    def keys(self) -> Iterable[str]:
        return self.data.keys()

    def __dir__(self) -> List[str]:
        return sorted(set(super().__dir__()) | set(self.data))

    def to_dict(self) -> Dict[str, Any]:
        return _plain(self.data)

    def _frame(self, columns: Dict[str, Any]):
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - optional dependency
            raise ImportError("to_pandas() needs pandas: pip install pandas") from e
        return pd.DataFrame(columns)

    def __repr__(self) -> str:
        scalars = {k: v for k, v in self.data.items() if isinstance(v, (int, float, str))}
        shown = ", ".join(f"{k}={v!r}" for k, v in list(scalars.items())[:6])
        return f"{type(self).__name__}({shown}, ...)"


def _plain(v: Any) -> Any:
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    if isinstance(v, list):
        return [_plain(x) for x in v]
    return v


class ProfileResult(Result):
    """The disc profile (``rvlife profile``): ``x_mm``, ``y_mm`` (disc frame), ``mesh_angle_deg``
    (0 root, 180 tip), ``wear_um`` (depth along the normal), ``points_per_tooth``,
    ``max_wear_um``."""

    def to_pandas(self):
        return self._frame({k: self.data[k] for k in ("x_mm", "y_mm", "mesh_angle_deg", "wear_um")})


class ContactResult(Result):
    """Static equilibrium at one crank angle (``rvlife contact --json``): ``twist_arcmin``,
    ``first_contact_arcmin``, ``max_force_n``, ``max_pressure_mpa``,
    ``torsional_stiffness_nm_per_arcmin``, ``residual``, ``discs`` (per disc: translation,
    rotation, ``pins``)."""

    def to_pandas(self):
        """One row per disc and pin: mesh angle, gap, force, lever arm, half-width, pressure."""
        rows = [dict(disc=i + 1, **p) for i, d in enumerate(self.data["discs"]) for p in d["pins"]]
        return self._frame({k: [r[k] for r in rows] for k in rows[0]} if rows else {})


class TeResult(Result):
    """Static TE (``rvlife te --json``): ``te_mean_arcmin``, ``te_peak_to_peak_arcmin``,
    ``angular_te_arcmin``, ``backlash_arcmin``, ``lost_motion_arcmin``,
    ``torsional_stiffness_nm_per_arcmin``, and over an output revolution ``input_deg`` and
    ``te_arcmin`` (with a torque: ``loaded_te_arcmin``)."""

    def to_pandas(self):
        cols = {"input_deg": self.data["input_deg"], "te_arcmin": self.data["te_arcmin"]}
        if "loaded_te_arcmin" in self.data:
            cols["loaded_te_arcmin"] = self.data["loaded_te_arcmin"]
        return self._frame(cols)


class HysteresisResult(Result):
    """The hysteresis curve (``rvlife hysteresis --json``): ``torque_nm``, ``twist_arcmin``
    (mean over a mesh cycle), ``backlash_arcmin``, ``lost_motion_arcmin``,
    ``hysteresis_loss_arcmin``, ``torsional_stiffness_nm_per_arcmin``, and ``at_crank_angle``."""

    def to_pandas(self):
        return self._frame({"torque_nm": self.data["torque_nm"], "twist_arcmin": self.data["twist_arcmin"]})


class DynamicsResult(Result):
    """A multibody simulation (``rvlife dynamics --json`` without ``wall_time_s``):
    ``te_mean_arcmin``, ``te_peak_to_peak_arcmin``, ``te_rms_arcmin``, ... and ``samples``, the
    time series (``time_s``, ``te_arcmin``, ``input_speed_deg_s``, ``load_nm``, ...)."""

    def to_pandas(self):
        """The time series, one row per sample (``pins_in_contact`` as two columns)."""
        s = dict(self.data["samples"])
        pins = s.pop("pins_in_contact", None)
        if pins is not None:
            s["pins_in_contact_disc1"] = [p[0] for p in pins]
            s["pins_in_contact_disc2"] = [p[1] for p in pins]
        return self._frame(s)


@dataclass(frozen=True)
class Quantity:
    """One quantity of a study's stages, as the library's table declares it: ``name`` (with its
    unit, the key of ``summary.json``), ``unit``, ``label``, ``description``, ``models`` (the
    model that produces it: ``static``, ``dynamics`` or ``flexible``) and ``columns`` (its
    ``stages.csv`` columns: the name, or two for a smallest-largest pair)."""

    name: str
    unit: str
    label: str
    description: str
    models: str
    columns: tuple


def quantities() -> List[Quantity]:
    """Every quantity of a study's stages, in the order of ``summary.json`` and ``stages.csv``
    (the library's table: ``rvlife run --all`` prints them all)."""
    return [Quantity(n, u, l, d, m, tuple(c)) for (n, u, l, d, m, c) in _rvlife.quantities()]


class StudyResult(Result):
    """The accuracy-life study (``summary.json`` of ``rvlife run``): ``stages`` (one dict per
    stage), ``paper_comparison``, ``accuracy_life``, ...; ``out`` is the results directory when
    one was written. Every stage quantity of :func:`quantities` is also an attribute, a numpy
    array over the stages (``study.lost_motion_arcmin``; NaN where its model did not run; a
    smallest-largest pair as an array of pairs)."""

    out: Optional[Path] = None

    def __getattr__(self, name: str) -> Any:
        try:
            return self.__dict__["data"][name]
        except KeyError:
            pass
        if any(q.name == name for q in quantities()):
            values = [s.get(name, math.nan) for s in self.__dict__["data"]["stages"]]
            return np.array([v if v is not None else math.nan for v in values], dtype=float)
        raise AttributeError(name)

    def __dir__(self) -> List[str]:
        return sorted(set(super().__dir__()) | {q.name for q in quantities()})

    def to_pandas(self):
        """The stage table (``stages.csv``): one row per stage, a column per column of every
        quantity of :func:`quantities` (empty where its model did not run)."""
        stages = self.data["stages"]
        cols: Dict[str, list] = {}
        for q in quantities():
            for i, c in enumerate(q.columns):
                cols[c] = [
                    _column_value(s.get(q.name), i, len(q.columns)) for s in stages
                ]
        return self._frame(cols)


def _column_value(v: Any, i: int, n: int) -> float:
    """Column ``i`` of ``n`` of a quantity's value (NaN when absent)."""
    if v is None:
        return math.nan
    if n > 1:
        return float(v[i])
    return float(v)


class MonteCarloResult(Result):
    """A Monte Carlo run: ``samples`` and ``stages`` tables (the CSV files' columns) and, when a
    results directory was written (``out``), its ``summary.json`` as ``summary``."""

    out: Optional[Path] = None

    def to_pandas(self):
        """``(samples, stages)`` data frames."""
        import io

        import pandas as pd

        return (
            pd.read_csv(io.StringIO(self.data["samples_csv"])),
            pd.read_csv(io.StringIO(self.data["stages_csv"])),
        )


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
    model after ``hours`` (h); ``nominal`` drops the modifications. ``points_per_tooth`` 0 takes
    the export's default."""
    c = _cfg(config)
    return ProfileResult(_rvlife.profile(*c._args(), wear_um, hours, nominal, points_per_tooth, progress))


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
    ``torque_nm`` (N m), input locked."""
    c = _cfg(config)
    return ContactResult(_rvlife.contact(*c._args(), crank_deg, torque_nm, wear_um, hours, progress))


def te(
    config: Optional[Config] = None,
    *,
    torque_nm: Optional[float] = None,
    wear_um: Optional[float] = None,
    hours: Optional[float] = None,
    progress: Optional[Progress] = None,
) -> TeResult:
    """STE, backlash, lost motion and torsional stiffness over a mesh cycle, STE over an output
    revolution; with ``torque_nm`` (N m) also the loaded TE."""
    c = _cfg(config)
    return TeResult(_rvlife.te(*c._args(), torque_nm, wear_um, hours, progress))


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
    return HysteresisResult(_rvlife.hysteresis(*c._args(), crank_deg, levels, wear_um, hours, progress))


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
    """Multibody simulation of the whole reducer: ``load`` overrides ``[dynamics.load] kind``
    (``none``, ``constant``, ``sinusoidal``, ``table``), ``torque_nm`` a constant load's torque,
    ``disc`` the disc model (``rigid`` or ``flexible``); ``out`` also writes the results
    directory."""
    c = _cfg(config)
    return DynamicsResult(
        _rvlife.dynamics(
            *c._args(),
            load,
            torque_nm,
            disc,
            wear_um,
            hours,
            pin_forces,
            None if out is None else os.fspath(out),
            force,
            progress,
        )
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
    r = StudyResult(_rvlife.run_study(*c._args(), None if out is None else os.fspath(out), force, progress))
    r.out = None if out is None else Path(out)
    return r


@dataclass
class MonteCarlo:
    """A Monte Carlo plan for :func:`sweep`: ``samples`` reducers drawn from the config's
    ``[tolerances]`` with ``seed`` (as ``rvlife montecarlo``)."""

    config: Optional[Config]
    samples: int
    seed: int = 0
    full_wear: bool = False
    samples_per_mesh_cycle: int = 4


def montecarlo(
    config: Optional[Config] = None,
    *,
    samples: int,
    seed: int = 0,
    shard: Optional[str] = None,
    full_wear: bool = False,
    samples_per_mesh_cycle: int = 4,
    out: Optional[PathLike] = None,
    force: bool = False,
    progress: Optional[Progress] = None,
) -> MonteCarloResult:
    """Monte Carlo over ``[tolerances]`` (``rvlife montecarlo``): ``samples`` sampled reducers
    of ``seed``, or the shard ``"I/N"`` of them; ``out`` writes the command line's files."""
    c = _cfg(config)
    r = MonteCarloResult(
        _rvlife.montecarlo(
            *c._args(),
            samples,
            seed,
            shard,
            full_wear,
            samples_per_mesh_cycle,
            None if out is None else os.fspath(out),
            force,
            progress,
        )
    )
    return _with_summary(r, out)


def _with_summary(r: MonteCarloResult, out: Optional[PathLike]) -> MonteCarloResult:
    r.out = None if out is None else Path(out)
    if r.out is not None and (r.out / "summary.json").is_file():
        r.data["summary"] = json.loads((r.out / "summary.json").read_text())
    return r


def _shard_task(config: tuple, mc: tuple, shard: str) -> Dict[str, str]:
    """One shard of a Monte Carlo run, on a worker: its records and meta-data as texts."""
    samples, seed, full_wear, per_cycle = mc
    args = Config(*config)._args()
    return _rvlife.montecarlo(*args, samples, seed, shard, full_wear, per_cycle, None, False, None)


def _study_task(config: tuple, out: Optional[str], force: bool) -> Dict[str, Any]:
    """One study, on a worker (writing ``out`` when given: workers must see that folder)."""
    return _rvlife.run_study(*Config(*config)._args(), out, force, None)


def sweep(
    configs_or_samples: Union[MonteCarlo, Sequence[Config]],
    client: Any = None,
    *,
    out: Optional[PathLike] = None,
    force: bool = False,
    tasks: Optional[int] = None,
) -> Union[MonteCarloResult, List[StudyResult]]:
    """Runs studies or Monte Carlo samples on a ``dask.distributed`` client and gathers the
    results in order.

    - A :class:`MonteCarlo` plan is split into ``tasks`` shards (default: twice the workers, at
      most one per sample); each worker runs its shard (as ``rvlife montecarlo --shard I/N``),
      and the shards are merged into exactly the serial run's records; ``out`` gets the same
      files as ``rvlife montecarlo`` (the merge of ``rvlife merge``).
    - A list of :class:`Config` runs one study each; with ``out``, study ``k`` writes
      ``out/study_<k>`` (the files of ``rvlife run``).

    ``client`` is any ``dask.distributed.Client`` (a ``LocalCluster``'s, or e.g. dask-jobqueue's
    ``SLURMCluster``'s); ``None`` starts a ``LocalCluster`` for the call and closes it after.
    """
    from dask.distributed import Client, LocalCluster

    own = client is None
    cluster = None
    if own:
        cluster = LocalCluster(processes=True, threads_per_worker=1)
        client = Client(cluster)
    try:
        if isinstance(configs_or_samples, MonteCarlo):
            mc = configs_or_samples
            c = _cfg(mc.config)
            workers = max(1, len(client.scheduler_info().get("workers", {})))
            n = tasks if tasks is not None else 2 * workers
            n = max(1, min(int(n), mc.samples))
            plan = (mc.samples, mc.seed, mc.full_wear, mc.samples_per_mesh_cycle)
            futures = [client.submit(_shard_task, c._text(), plan, f"{i}/{n}", pure=False) for i in range(1, n + 1)]
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
                target = Path(out) if out is not None else Path(tmp) / "merged"
                _rvlife.merge(dirs, str(target), force)
                data = {
                    "samples_csv": (target / "samples.csv").read_text(),
                    "stages_csv": (target / "stages.csv").read_text(),
                    "summary": json.loads((target / "summary.json").read_text()),
                }
            r = MonteCarloResult(data)
            r.out = None if out is None else Path(out)
            return r
        configs = list(configs_or_samples)
        outs: List[Optional[str]] = [None] * len(configs)
        if out is not None:
            root = Path(out)
            root.mkdir(parents=True, exist_ok=True)
            outs = [str(root / f"study_{k}") for k in range(len(configs))]
        futures = [
            client.submit(_study_task, _cfg(c)._text(), o, force, pure=False)
            for c, o in zip(configs, outs)
        ]
        results = []
        for o, data in zip(outs, client.gather(futures)):
            r = StudyResult(data)
            r.out = None if o is None else Path(o)
            results.append(r)
        return results
    finally:
        if own:
            client.close()
            if cluster is not None:
                cluster.close()


def tqdm_progress(bar: Any) -> Progress:
    """A ``progress(done, total)`` callback that moves a tqdm bar:
    ``with tqdm() as bar: run_study(cfg, progress=tqdm_progress(bar))``."""

    def update(done: int, total: int) -> None:
        bar.total = total
        bar.n = done
        bar.refresh()

    return update
