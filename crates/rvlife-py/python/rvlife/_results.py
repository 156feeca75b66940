"""Typed results of the commands: every attribute declared here (what type checkers and
editors see), filled from the command's JSON output, numeric series as numpy ``float64``
arrays, tables as pandas DataFrames. Units are in the names (``_arcmin``, ``_um``, ``_nm``
newton metres, ``_n`` newtons, ``_mpa``, ``_h`` hours, ``_deg``)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Tuple

import numpy as np
import numpy.typing as npt
import pandas as pd

from . import _rvlife

Array = npt.NDArray[np.float64]


def _plain(v: Any) -> Any:
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    if isinstance(v, list):
        return [_plain(x) for x in v]
    return v


def _fields(cls: type) -> List[str]:
    """The attributes a result class declares (its annotations and its bases'), in order."""
    names: List[str] = []
    for c in reversed(cls.__mro__):
        if c in (object, Result):
            continue
        for n in c.__dict__.get("__annotations__", {}):
            if not n.startswith("_") and n not in names and n != "out":
                names.append(n)
    return names


class Result:
    """A command's result. Each declared attribute is a key of the command's JSON output
    (``rvlife <command> --json``); :meth:`to_dict` gives that JSON back (arrays as lists),
    ``r["key"]`` reads any key."""

    _data: Dict[str, Any]

    def __init__(self, data: Dict[str, Any]):
        self._data = data
        for name in _fields(type(self)):
            setattr(self, name, data.get(name))

    def __getitem__(self, key: str) -> Any:
        return self._data[key]

    def keys(self) -> Iterable[str]:
        """The keys of the JSON output."""
        return self._data.keys()

    def to_dict(self) -> Dict[str, Any]:
        """The command line's JSON object (arrays as lists)."""
        return _plain(self._data)

    def _shown(self) -> List[str]:
        out = []
        for n in _fields(type(self)):
            v = getattr(self, n, None)
            if isinstance(v, float):
                out.append(f"{n}={v:.6g}")
            elif isinstance(v, (int, str)) and not isinstance(v, bool):
                out.append(f"{n}={v!r}")
            if len(out) == 4:
                break
        return out

    def __repr__(self) -> str:
        return f"{type(self).__name__}({', '.join(self._shown())}, ...)"


class ProfileResult(Result):
    """The disc profile (``rvlife profile``), in the disc frame."""

    points_per_tooth: int
    """Points per tooth."""
    max_wear_um: float
    """Largest wear depth, um."""
    x_mm: Array
    """x of each point, mm."""
    y_mm: Array
    """y of each point, mm."""
    mesh_angle_deg: Array
    """Mesh angle of each point, deg (0 root, 180 tip)."""
    wear_um: Array
    """Wear depth along the normal at each point, um."""

    def to_pandas(self) -> pd.DataFrame:
        """One row per point: ``x_mm``, ``y_mm``, ``mesh_angle_deg``, ``wear_um``."""
        return pd.DataFrame({k: self._data[k] for k in ("x_mm", "y_mm", "mesh_angle_deg", "wear_um")})


class ContactResult(Result):
    """Static equilibrium at one crank angle under an output torque, input locked
    (``rvlife contact --json``)."""

    crank_deg: float
    """Crank angle, deg."""
    torque_nm: float
    """Output torque, N m."""
    support: str
    """How the discs are supported: ``bearings`` or ``rigid``."""
    twist_arcmin: float
    """Output twist, arcmin."""
    first_contact_arcmin: float
    """Twist at the first contact (no load), arcmin."""
    max_force_n: float
    """Largest pin force, N."""
    pins_in_contact: int
    """Pins in contact, both discs."""
    max_pressure_mpa: float
    """Largest contact pressure, MPa."""
    torsional_stiffness_nm_per_arcmin: float
    """Tangent torsional stiffness at this torque, N m/arcmin."""
    residual: float
    """Relative residual of the equilibrium."""
    residual_roundoff_floor: float
    """The residual round-off alone can give."""
    max_wear_um: float
    """Largest wear depth of the profile, um."""
    discs: List[Dict[str, Any]]
    """Per disc: ``translation_um``, ``rotation_arcmin``, ``pin_moment_nm``, ``max_force_n``,
    ``pins_in_contact``, ``pin_forces_n`` and ``pins`` (one dict per pin)."""

    def to_pandas(self) -> pd.DataFrame:
        """One row per disc and pin: mesh angle, gap, force, lever arm, half-width, pressure."""
        rows = [dict(disc=i + 1, **p) for i, d in enumerate(self.discs) for p in d["pins"]]
        return pd.DataFrame(rows)


class TeResult(Result):
    """Static TE over a mesh cycle and an output revolution (``rvlife te --json``)."""

    max_wear_um: float
    """Largest wear depth, um."""
    support: str
    """``bearings`` or ``rigid``."""
    te_mean_arcmin: float
    """No-load STE, mean over a mesh cycle, arcmin."""
    te_peak_to_peak_arcmin: float
    """No-load STE peak to peak, arcmin."""
    te_reverse_mean_arcmin: float
    """STE turning the other way, mean, arcmin."""
    angular_te_arcmin: float
    """Angular TE over an output revolution (catalogue), arcmin."""
    backlash_arcmin: float
    """Backlash, mean over a mesh cycle, arcmin."""
    backlash_max_arcmin: float
    """Largest backlash over a mesh cycle, arcmin."""
    lost_motion_arcmin: float
    """Lost motion (catalogue: within +-3 % of rated torque), arcmin."""
    measuring_torque_nm: float
    """Torque of the lost motion, N m."""
    torsional_stiffness_nm_per_arcmin: float
    """Torsional stiffness b/a (catalogue), N m/arcmin."""
    samples_per_mesh_cycle: int
    """Crank angles per mesh cycle."""
    input_deg: Array
    """Input angle over an output revolution, deg."""
    te_arcmin: Array
    """No-load STE over an output revolution, arcmin."""
    torque_nm: Optional[float]
    """Torque of the loaded TE, N m (``None`` without ``torque_nm``)."""
    loaded_te_mean_arcmin: Optional[float]
    """Loaded TE, mean, arcmin."""
    loaded_te_peak_to_peak_arcmin: Optional[float]
    """Loaded TE peak to peak, arcmin."""
    max_force_n: Optional[float]
    """Largest pin force under the torque, N."""
    pins_in_contact: Optional[int]
    """Pins in contact under the torque."""
    loaded_te_arcmin: Optional[Array]
    """Loaded TE over an output revolution, arcmin."""

    def to_pandas(self) -> pd.DataFrame:
        """One row per input angle: ``input_deg``, ``te_arcmin`` (and ``loaded_te_arcmin``)."""
        cols: Dict[str, Any] = {"input_deg": self.input_deg, "te_arcmin": self.te_arcmin}
        if self.loaded_te_arcmin is not None:
            cols["loaded_te_arcmin"] = self.loaded_te_arcmin
        return pd.DataFrame(cols)


class EfficiencyResult(Result):
    """The power losses and efficiency over output speed, torque and oil temperature
    (``rvlife efficiency --json``)."""

    rated_torque_nm: float
    """Rated torque, N m."""
    rated_output_speed_rpm: float
    """Output speed at the rated input speed, rpm."""
    max_wear_um: float
    """Largest wear depth of the profile analysed, um."""
    samples_per_mesh_cycle: int
    """Crank angles per mesh cycle whose losses are averaged."""
    friction_model: str
    """``lambda`` (mixed lubrication) or ``constant``."""
    oil_viscosity_40_mm2_per_s: float
    """The oil's viscosity at 40 deg C, mm^2/s."""
    points: List[Dict[str, Any]]
    """Every operating point: ``output_speed_rpm``, ``torque_nm``, ``temperature_c``,
    ``efficiency``, the powers and losses (W) by contact kind, ``lambda_min``,
    ``lambda_mean``, ``film_min_um``, ``pin_friction_coefficient``."""
    at_rated: Dict[str, Any]
    """The same at the rated torque and speed."""

    def to_pandas(self) -> pd.DataFrame:
        """One row per operating point, the columns of ``points``."""
        return pd.DataFrame(self.points)


class HysteresisResult(Result):
    """The hysteresis curve, output torque 0 -> +rated -> -rated -> +rated, input locked
    (``rvlife hysteresis --json``); the top-level curve is the mean over a mesh cycle."""

    max_wear_um: float
    """Largest wear depth, um."""
    support: str
    """``bearings`` or ``rigid``."""
    rated_torque_nm: float
    """Rated torque, N m."""
    measuring_torque_fraction: float
    """Lost-motion measuring torque as a fraction of rated."""
    torsional_stiffness_definition: str
    """How the stiffness is read off the curve (b/a)."""
    crank_deg: float
    """Crank angle of ``at_crank_angle``, deg."""
    samples_per_mesh_cycle: int
    """Crank angles of the mean."""
    torque_nm: Array
    """Torque along the curve, N m."""
    twist_arcmin: Array
    """Twist along the curve (mean over a mesh cycle), arcmin."""
    backlash_arcmin: float
    """Backlash, arcmin."""
    lost_motion_arcmin: float
    """Lost motion, arcmin."""
    hysteresis_loss_arcmin: float
    """Hysteresis loss, arcmin."""
    torsional_stiffness_nm_per_arcmin: float
    """Torsional stiffness b/a, N m/arcmin."""
    at_crank_angle: Dict[str, Any]
    """The same curve and quantities at ``crank_deg``."""
    mesh_cycle_mean: Dict[str, Any]
    """The mean curve and quantities (as at the top level)."""
    twist_shares: List[Dict[str, Any]]
    """Share of the elastic twist at rated torque per part: ``part``, ``share``,
    ``twist_arcmin``."""

    def to_pandas(self) -> pd.DataFrame:
        """One row per point of the curve: ``torque_nm``, ``twist_arcmin``."""
        return pd.DataFrame({"torque_nm": self.torque_nm, "twist_arcmin": self.twist_arcmin})


class DynamicsResult(Result):
    """A multibody simulation (``rvlife dynamics --json`` without ``wall_time_s``): the summary
    as attributes, the time series in ``samples`` (and :meth:`to_pandas`)."""

    samples: Dict[str, Any]
    """The time series: ``time_s``, ``te_arcmin``, ``input_speed_deg_s``, ``load_nm``, ...
    (arrays), ``pins_in_contact`` (pairs)."""
    max_wear_um: float
    """Largest wear depth of the profile, um."""
    window_start_s: float
    """Start of the TE window, s."""
    window_end_s: float
    """End of the TE window, s."""
    te_mean_arcmin: float
    """DTE mean over the window, arcmin."""
    te_peak_to_peak_arcmin: float
    """DTE peak to peak over the window, arcmin."""
    te_rms_arcmin: float
    """DTE RMS over the window, arcmin."""
    te_min_arcmin: float
    """Smallest DTE over the window, arcmin."""
    te_max_arcmin: float
    """Largest DTE over the window, arcmin."""
    output_speed_deg_s: float
    """Mean output speed over the window, deg/s."""
    nominal_output_speed_deg_s: float
    """Input speed / i_H, deg/s."""
    max_pin_force_n: float
    """Largest pin force, N."""
    steps: int
    """Integrator steps."""
    rhs_evaluations: int
    """Right-hand-side evaluations."""
    jacobian_columns: int
    """Jacobian columns evaluated."""
    disc_modes: int
    """Elastic modes of each flexible disc (0: rigid discs)."""
    disc_mode_frequencies_hz: Optional[Array]
    """Their frequencies, Hz."""
    integrator: str
    """The integrator that ran."""
    integrator_fallback: Optional[str]
    """Why the implicit integrator was replaced, when it was."""
    pin_forces_n: Optional[List[List[float]]]
    """Every pin force at every sample (samples x pins of both discs), N; with
    ``pin_forces=True``."""

    def to_pandas(self) -> pd.DataFrame:
        """The time series, one row per sample (``pins_in_contact`` as two columns)."""
        s = dict(self.samples)
        pins = s.pop("pins_in_contact", None)
        if pins is not None:
            s["pins_in_contact_disc1"] = [p[0] for p in pins]
            s["pins_in_contact_disc2"] = [p[1] for p in pins]
        return pd.DataFrame(s)


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
    columns: Tuple[str, ...]


_QUANTITIES: Optional[List[Quantity]] = None


def quantities() -> List[Quantity]:
    """Every quantity of a study's stages, in the order of ``summary.json`` and ``stages.csv``
    (the library's table: ``rvlife run --all`` prints them all)."""
    global _QUANTITIES
    if _QUANTITIES is None:
        _QUANTITIES = [Quantity(n, u, l, d, m, tuple(c)) for (n, u, l, d, m, c) in _rvlife.quantities()]
    return list(_QUANTITIES)


def _column_value(v: Any, i: int, n: int) -> float:
    if v is None:
        return math.nan
    return float(v[i]) if n > 1 else float(v)


def stage_table(stages: List[Dict[str, Any]]) -> pd.DataFrame:
    """The stage table of ``stages.csv``: one row per stage, the columns of every quantity of
    :func:`quantities` (NaN where its model did not run; the losses' only where a stage has
    them)."""
    cols: Dict[str, List[float]] = {}
    for q in quantities():
        # The losses' columns only where a stage has them, as stages.csv writes them.
        if q.models == "lubrication" and all(s.get(q.name) is None for s in stages):
            continue
        for i, c in enumerate(q.columns):
            cols[c] = [_column_value(s.get(q.name), i, len(q.columns)) for s in stages]
    return pd.DataFrame(cols)


class StudyResult(Result):
    """The accuracy-life study (``summary.json`` of ``rvlife run``). Every stage quantity of
    :func:`quantities` is also an attribute, a numpy array over the stages
    (``study.lost_motion_arcmin``; NaN where its model did not run)."""

    rvlife_version: str
    """Version that ran the study."""
    ratio: float
    """Overall ratio i_H."""
    wear_model: str
    """``flodin`` or ``paper``."""
    archard_coefficient_mm3_per_n_m: float
    """Archard coefficient of the disc, mm^3/(N m)."""
    rated_torque_nm: float
    """Rated torque, N m."""
    loaded_te_torque_nm: float
    """Torque of the loaded TE, N m."""
    mesh_cycles_per_hour: float
    """Mesh cycles per working hour of each tooth."""
    wear_rate_evaluations: int
    """Wear-rate evaluations of the integration."""
    stages: List[Dict[str, Any]]
    """One dict per stage, every quantity of :func:`quantities`."""
    validity_limit: Optional[Dict[str, Any]]
    """Where the wear model leaves its validity (``None``: beyond the last stage)."""
    accuracy_life: Optional[Dict[str, Any]]
    """``accuracy_life_h``, ``limited_by``, ``horizon_h`` (``None`` without a spec)."""
    measured_profile_fit: Optional[Dict[str, Any]]
    """The measured profile's fit, when the config has one."""
    paper_comparison: Optional[Dict[str, Any]]
    """Against the paper's numbers (the paper's reducer only)."""
    verdict: str
    """The verdict in one line: the accuracy life and what limits it, against the spec."""
    out: Optional[Path] = None
    """The results directory written (``None``: none)."""

    def __init__(self, data: Dict[str, Any], verdict: str = "", out: Optional[Path] = None):
        super().__init__(data)
        self.verdict = verdict
        self.out = out

    def __getattr__(self, name: str) -> Array:
        if name.startswith("_") or not any(q.name == name for q in quantities()):
            raise AttributeError(name)
        values = [s.get(name, math.nan) for s in self._data["stages"]]
        return np.array([v if v is not None else math.nan for v in values], dtype=float)

    def __dir__(self) -> List[str]:
        return sorted(set(super().__dir__()) | {q.name for q in quantities()})

    def to_pandas(self) -> pd.DataFrame:
        """The stage table (``stages.csv``)."""
        return stage_table(self.stages)

    def __repr__(self) -> str:
        life = self.accuracy_life or {}
        hours = life.get("accuracy_life_h")
        shown = "no spec" if not life else (
            f"accuracy_life_h={hours:.0f}" if hours is not None else f"within spec to {life.get('horizon_h', 0):.0f} h"
        )
        return f"StudyResult({len(self.stages)} stages, {shown}{', out=' + repr(str(self.out)) if self.out else ''})"


class AccuracyLifeResult(Result):
    """The accuracy life of a config: the study without its dynamic and FE analyses (they do
    not enter the life), as ``summary.json``'s ``accuracy_life`` gives it."""

    accuracy_life_h: Optional[float]
    """Hours at which the reducer leaves its spec, h (``None``: not within the horizon)."""
    limited_by: Optional[str]
    """The ``[life]`` key crossed first."""
    horizon_h: Optional[float]
    """Hours studied, h (``None`` without a spec)."""
    verdict: str
    """The verdict in one line."""
    hours: Array
    """Working hours of the stages, h."""
    lost_motion_arcmin: Array
    """Lost motion at each stage, arcmin."""
    backlash_arcmin: Array
    """Backlash at each stage, arcmin."""
    angular_te_arcmin: Array
    """Angular TE at each stage, arcmin."""
    torsional_stiffness_nm_per_arcmin: Array
    """Torsional stiffness at each stage, N m/arcmin."""
    max_wear_um: Optional[float]
    """Largest wear depth at the last stage, um."""

    def __repr__(self) -> str:
        return f"AccuracyLifeResult({self.verdict!r})"


class ArchardFit(Result):
    """The Archard coefficient that gives a target largest wear at the last stage
    (``rvlife calibrate``)."""

    archard_coefficient_mm3_per_n_m: float
    """The coefficient, mm^3/(N m) (the key ``wear.archard_coefficient_mm3_per_n_m``)."""
    archard_coefficient_m2_per_n: float
    """The same, m^2/N."""
    max_wear_um: float
    """Largest wear it gives at the last stage, um."""
    hours: float
    """The last stage, h."""


class StructureFit(Result):
    """The structure compliance fitted to a measured hysteresis curve or a catalogue
    stiffness (``calibrate --measured CURVE`` or ``--catalogue-stiffness-nm-per-arcmin``,
    ``calibration.json``); :attr:`calibrated` is the config with the fitted key set (the
    command line's ``calibrated.toml``)."""

    target: str
    """``"hysteresis curve"`` or ``"catalogue stiffness"``."""
    compliance_arcmin_per_knm: Dict[str, float]
    """Fitted compliance and its 95 % interval (``value``, ``lower``, ``upper``), arcmin per
    kN m (the key ``reducer.structure.compliance_arcmin_per_knm``)."""
    config_compliance_arcmin_per_knm: float
    """The config's own compliance, arcmin per kN m."""
    model_stiffness_nm_per_arcmin: float
    """The model's ``b/a`` with the config's compliance, N m/arcmin."""
    fitted_stiffness_nm_per_arcmin: float
    """The model's ``b/a`` with the fitted compliance, N m/arcmin."""
    offset_arcmin: Optional[float]
    """The bench's zero, arcmin (curve only)."""
    extra_play_arcmin: Optional[float]
    """How far the measured loading sides lie apart beyond the model's, arcmin (curve only)."""
    rms_residual_arcmin: Optional[float]
    """RMS residual of the fitted rows, arcmin (curve only)."""
    points: int
    """Rows fitted."""
    degrees_of_freedom: int
    """Degrees of freedom of the interval."""
    calibrated: Any = None
    """The input :class:`Config` with the fitted compliance set (rounded to 1e-4, as the
    command line writes it)."""


class Calibration(Result):
    """The fit of the Archard coefficient to measurements (``calibrate --measured``,
    ``calibration.json``): estimates as dicts ``value``, ``lower``, ``upper``."""

    archard_coefficient_m2_per_n: Dict[str, float]
    """Fitted coefficient and its interval, m^2/N."""
    archard_coefficient_mm3_per_n_m: Dict[str, float]
    """The same, mm^3/(N m)."""
    config_archard_coefficient_m2_per_n: float
    """The config's coefficient, m^2/N."""
    ln_k_standard_error: float
    """Standard error of ln k."""
    running_in_backlash_arcmin: Optional[Dict[str, float]]
    """Running-in play b0 and its interval, arcmin (with ``fit_running_in=True``)."""
    running_in_factor: Optional[Dict[str, float]]
    """Running-in factor and its interval (when the config has one)."""
    running_in_hours: Optional[float]
    """Running-in time constant, h (the config's)."""
    confidence: float
    """Confidence level of the intervals."""
    interval_method: str
    """How the intervals are found."""
    points: int
    """Measured values."""
    parameters: int
    """Fitted parameters."""
    degrees_of_freedom: int
    """Degrees of freedom."""
    t_quantile: float
    """Student-t quantile used."""
    residual_variance: float
    """Residual variance of the weighted fit."""
    quantities: List[Dict[str, Any]]
    """Per measured quantity: column, unit, points, RMS residual."""
    residuals: List[Dict[str, Any]]
    """Every measured value against the model."""
    curves: List[Dict[str, Any]]
    """Model curves."""
    reference_archard_coefficient_m2_per_n: float
    """Coefficient of the last reference study, m^2/N."""
    reference_hours: float
    """Hours of the last reference study, h."""
    reference_runs: int
    """Reference studies run."""
    reference_stages: int
    """Stages analysed over all reference studies."""
    out: Optional[Path] = None
    """The results directory written (``None``: none)."""

    def residuals_frame(self) -> pd.DataFrame:
        """Every measured value against the model, one row each."""
        return pd.DataFrame(self.residuals)

    def __repr__(self) -> str:
        k = self.archard_coefficient_mm3_per_n_m
        return (
            f"Calibration(archard_coefficient_mm3_per_n_m={k['value']:.4e} "
            f"[{k['lower']:.4e}, {k['upper']:.4e}], points={self.points})"
        )


class MonteCarloResult:
    """A Monte Carlo run: its tables as DataFrames (the CSV files' columns) and, when a results
    directory was written (``out``), its ``summary.json``."""

    samples: pd.DataFrame
    """One row per sampled reducer (``samples.csv``): its status, accuracy life, what limits
    it, where a sample within spec is censored (``censored_h``), and its part errors."""
    stages: pd.DataFrame
    """One row per sample and stage (``stages.csv``): the accuracy quantities."""
    summary: Optional[Dict[str, Any]]
    """``summary.json`` (percentiles, the life distribution, the verdict) when written."""
    out: Optional[Path]
    """The results directory (``None``: none written)."""

    def __init__(self, samples_csv: str, stages_csv: str, summary: Optional[Dict[str, Any]] = None, out: Optional[Path] = None):
        import io

        self._samples_csv = samples_csv
        self._stages_csv = stages_csv
        self.samples = pd.read_csv(io.StringIO(samples_csv))
        self.stages = pd.read_csv(io.StringIO(stages_csv))
        self.summary = summary
        self.out = out

    def to_pandas(self) -> Tuple[pd.DataFrame, pd.DataFrame]:
        """``(samples, stages)``."""
        return self.samples, self.stages

    def __repr__(self) -> str:
        n = len(self.samples)
        ok = int((self.samples["status"] == "ok").sum()) if "status" in self.samples else n
        verdict = ""
        if self.summary and isinstance(self.summary.get("verdict"), str):
            verdict = f", {self.summary['verdict'][:80]!r}"
        where = f", out={str(self.out)!r}" if self.out else ""
        return f"MonteCarloResult({n} samples, {ok} ok{verdict}{where})"
