"""rvlife: accuracy-life prediction of RV reducers and cycloid drives, from Python.

Every command of the ``rvlife`` command line is a function here, running the same Rust code
with the same validation: :func:`profile`, :func:`contact`, :func:`te`, :func:`hysteresis`, :func:`efficiency`,
:func:`dynamics`, :func:`run_study`, :func:`accuracy_life`, :func:`calibrate`,
:func:`calibrate_structure`, :func:`montecarlo` and :func:`merge` take a :class:`Config` (or ``None``: the built-in example)
and return a typed result whose attributes are the keys of the command's JSON output, numeric
series as numpy ``float64`` arrays, tables as pandas DataFrames. Units are in the names:
``_mm``, ``_um``, ``_deg``, ``_arcmin``, ``_nm`` (newton metres), ``_n``, ``_mpa``, ``_h``,
``_s``.

Configs are values: ``example().replace({"cycloid.eccentricity_mm": 1.25})``,
``Config.from_dict({"cycloid": {"pins": 38}})`` (merged over the example), ``to_dict()``,
``to_toml()``. :func:`grid` and :func:`sweep` run design sweeps into one tidy DataFrame, in
this process or on a ``dask.distributed`` client.

Bad input raises ``ValueError`` with the command line's message in Python's spelling: it names
the key (or the keyword argument), the value and the allowed range. Solves release the GIL;
``progress`` is a callable ``progress(done, total)`` with ``done`` never decreasing (e.g.
:func:`tqdm_progress` of a tqdm bar).
"""

from __future__ import annotations

from . import _rvlife
from ._commands import (
    Progress,
    accuracy_life,
    calibrate,
    calibrate_structure,
    contact,
    dynamics,
    efficiency,
    hysteresis,
    merge,
    montecarlo,
    profile,
    run_study,
    te,
    tqdm_progress,
)
from ._config import DEFAULT_WORK_BUDGET_MIN, Config, example, presets
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
    Quantity,
    Result,
    StructureFit,
    StudyResult,
    TeResult,
    quantities,
)
from ._sweep import MonteCarlo, OptimizeResult, grid, optimize, sweep

__version__: str = _rvlife.version()

from ._declared import document as _document  # noqa: E402

_document(globals())

__all__ = [
    "Config",
    "DEFAULT_WORK_BUDGET_MIN",
    "example",
    "presets",
    "Result",
    "ProfileResult",
    "ContactResult",
    "TeResult",
    "HysteresisResult",
    "EfficiencyResult",
    "DynamicsResult",
    "StudyResult",
    "AccuracyLifeResult",
    "ArchardFit",
    "Calibration",
    "StructureFit",
    "MonteCarloResult",
    "Quantity",
    "quantities",
    "Progress",
    "profile",
    "contact",
    "te",
    "hysteresis",
    "efficiency",
    "dynamics",
    "run_study",
    "accuracy_life",
    "calibrate",
    "calibrate_structure",
    "montecarlo",
    "merge",
    "grid",
    "sweep",
    "MonteCarlo",
    "optimize",
    "OptimizeResult",
    "tqdm_progress",
]
