"""The Python package against the command line: same validation, same numbers, the Dask sweep
equal to the serial Monte Carlo run. The command line binary is `RVLIFE_BIN` or the workspace's
`target/release/rvlife`."""

import json
import re
import math
import os
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import rvlife

ROOT = Path(__file__).resolve().parents[3]
BIN = os.environ.get("RVLIFE_BIN", str(ROOT / "target" / "release" / "rvlife"))


def cli(*args, cwd=None):
    """Runs the command line; returns stdout (the test fails on a non-zero exit)."""
    o = subprocess.run([BIN, *map(str, args)], capture_output=True, text=True, cwd=cwd)
    assert o.returncode == 0, f"rvlife {' '.join(map(str, args))}: {o.stderr}"
    return o.stdout


def cli_json(*args):
    return json.loads(cli(*args))


def same(a, b, path="$"):
    """Exact equality of two JSON-like values (floats bit for bit)."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and set(a) == set(b), f"{path}: keys {sorted(set(a) ^ set(b))}"
        for k in a:
            same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), f"{path}: lengths"
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{path}[{i}]")
    elif isinstance(a, float) or isinstance(b, float):
        assert float(a) == float(b) or (math.isnan(a) and math.isnan(b)), f"{path}: {a!r} != {b!r}"
    else:
        assert a == b, f"{path}: {a!r} != {b!r}"


def short_text(dynamics=False, fem=False, lubrication=False):
    """The paper's reducer with three stages (0, 250, 500 h); the dynamic model (0.15 s), the FE
    disc and the losses (`[lubrication] enabled`) when asked."""
    lines = []
    section = ""
    for line in rvlife._rvlife.example_toml("paper").splitlines():
        s = line.strip()
        if s.startswith("["):
            section = s.strip("[]").split("]")[0]
        # The preset's spec and tolerances are left out: tests add their own.
        if section in ("tolerances", "life") and s and not s.startswith("#"):
            continue
        if s.startswith("stage_hours ="):
            line = "stage_hours = [0.0, 250.0, 500.0]"
        elif s.startswith("profile_update_hours ="):
            line = "profile_update_hours = 250.0"
        elif section == "dynamics" and s.startswith("enabled ="):
            line = f"enabled = {'true' if dynamics else 'false'}"
        elif section == "fem" and s.startswith("enabled ="):
            line = f"enabled = {'true' if fem else 'false'}"
        elif section == "lubrication" and s.startswith("enabled ="):
            line = f"enabled = {'true' if lubrication else 'false'}"
        elif section == "dynamics" and s.startswith("end_time_s ="):
            line = "end_time_s = 0.15"
        elif section == "dynamics" and s.startswith("window_s ="):
            line = "window_s = [0.1, 0.15]"
        lines.append(line)
    return "\n".join(lines) + "\n"


MC_TOLERANCES = """
[tolerances]
pin_radial_um = { normal = 1.0 }
pin_tangential_um = { normal = 1.0 }
pin_radius_um = { iso_grade = 5 }
crank_eccentricity_um = { normal = 1.0 }
equidistant_um = { normal = 0.5 }

[life]
lost_motion_arcmin = 2.3
"""


def mc_text():
    t = short_text().replace("equidistant_mm = 0.0 ", "equidistant_mm = 0.008 ")
    return t + MC_TOLERANCES


@pytest.fixture(scope="module")
def tmp(tmp_path_factory):
    return tmp_path_factory.mktemp("rvlife")


def write(tmp, name, text):
    p = tmp / name
    p.write_text(text)
    return p


# --- validation -------------------------------------------------------------------------


def test_bad_values_raise_value_error_naming_the_key():
    text = rvlife._rvlife.example_toml("paper").replace("rated_torque_nm = 412.0", "rated_torque_nm = -5.0")
    with pytest.raises(ValueError, match=r"rated_torque_nm = -5"):
        rvlife.Config.from_toml(text)
    with pytest.raises(ValueError, match=r"wear\.extra.*unknown field"):
        rvlife.Config.from_toml(rvlife._rvlife.example_toml("paper") + "\n[wear.extra]\nno_such_key = 1\n")
    with pytest.raises(ValueError, match="torque_nm"):
        rvlife.te(torque_nm=float("nan"))
    with pytest.raises(ValueError, match="wear_um"):
        rvlife.profile(wear_um=-1.0)
    with pytest.raises(ValueError, match="levels"):
        rvlife.hysteresis(levels=0)
    with pytest.raises(ValueError, match="rv-999"):
        rvlife.example("rv-999")


def test_the_same_message_as_the_command_line(tmp):
    text = rvlife._rvlife.example_toml("paper").replace("pin_radius_mm = 3.0", "pin_radius_mm = -3.0")
    cfg = write(tmp, "bad.toml", text)
    o = subprocess.run([BIN, "te", str(cfg)], capture_output=True, text=True)
    assert o.returncode == 2
    with pytest.raises(ValueError) as e:
        rvlife.Config.from_file(cfg)
    assert str(e.value) in o.stderr, (str(e.value), o.stderr)


def test_dict_config_equals_its_toml():
    import tomllib

    d = tomllib.loads(rvlife._rvlife.example_toml())
    same(rvlife.te(rvlife.Config.from_dict(d), wear_um=5.0).to_dict(), rvlife.te(wear_um=5.0).to_dict())
    d["cycloid"]["pin_radius_mm"] = -3.0
    with pytest.raises(ValueError, match="pin_radius_mm = -3"):
        rvlife.Config.from_dict(d)


# --- results equal the command line's JSON --------------------------------------------------


def test_te_equals_cli_json():
    r = rvlife.te(torque_nm=412.0, wear_um=10.0)
    assert isinstance(r.te_arcmin, np.ndarray) and r.te_arcmin.dtype == np.float64
    same(r.to_dict(), cli_json("te", "--json", "--torque-nm", 412, "--wear-um", 10))
    df = r.to_pandas()
    assert list(df.columns) == ["input_deg", "te_arcmin", "loaded_te_arcmin"]
    assert len(df) == len(r.input_deg)


def test_contact_and_hysteresis_equal_cli_json():
    r = rvlife.contact(crank_deg=3.0, torque_nm=200.0, wear_um=10.0)
    same(r.to_dict(), cli_json("contact", "--json", "--crank-deg", 3, "--torque-nm", 200, "--wear-um", 10))
    assert len(r.to_pandas()) == sum(len(d["pins"]) for d in r.discs)
    h = rvlife.hysteresis(crank_deg=2.0, levels=4)
    same(h.to_dict(), cli_json("hysteresis", "--json", "--crank-deg", 2, "--levels", 4))


def test_efficiency_equals_cli_json_and_its_csv(tmp):
    e = rvlife.efficiency(speeds_rpm=[5, 15], torques_nm=[206.0, 412.0], temperatures_c=[40, 60])
    same(
        e.to_dict(),
        cli_json("efficiency", "--json", "--speeds-rpm", "5,15", "--torques-nm", "206,412", "--temperatures-c", "40,60"),
    )
    f = e.to_pandas()
    assert len(f) == 8 and (f["efficiency"] > 0.5).all() and (f["efficiency"] < 1.0).all()
    out = tmp / "map.csv"
    cli("efficiency", "--speeds-rpm", "5,15", "--torques-nm", "206,412", "--temperatures-c", "40,60", "--out", out)
    import pandas as pd

    c = pd.read_csv(out)
    assert np.allclose(c["efficiency"], f["efficiency"], atol=1e-6)
    with pytest.raises(ValueError, match="speeds_rpm"):
        rvlife.efficiency(speeds_rpm=[0.0])


def test_profile_equals_cli_csv(tmp):
    import pandas as pd

    out = tmp / "profile.csv"
    cli("profile", "--out", out, "--wear-um", 20, "--force")
    f = pd.read_csv(out)
    p = rvlife.profile(wear_um=20.0)
    for k in ("x_mm", "y_mm", "mesh_angle_deg", "wear_um"):
        # The CSV rounds to 9 decimals.
        assert np.max(np.abs(f[k].to_numpy() - p[k])) < 1e-8, k


def test_dynamics_equals_cli_json(tmp):
    cfg = write(tmp, "dyn.toml", short_text(dynamics=True))
    c = rvlife.Config.from_file(cfg)
    r = rvlife.dynamics(c, load="constant", torque_nm=300.0)
    v = cli_json("dynamics", cfg, "--json", "--load", "constant", "--torque-nm", 300)
    del v["wall_time_s"]
    d = r.to_dict()
    samples = d.pop("samples")
    same(d, v)
    assert len(samples["time_s"]) == len(r.to_pandas()) > 10
    with pytest.raises(ValueError, match="torque_nm"):
        rvlife.dynamics(c, load="sinusoidal", torque_nm=300.0)


def test_study_equals_cli_summary(tmp):
    cfg = write(tmp, "short.toml", short_text())
    out_cli = tmp / "study_cli"
    cli("run", cfg, "--out", out_cli)
    calls = []
    out_py = tmp / "study_py"
    r = rvlife.run_study(rvlife.Config.from_file(cfg), out=out_py, progress=lambda d, t: calls.append((d, t)))
    same(r.to_dict(), json.loads((out_cli / "summary.json").read_text()))
    same(json.loads((out_py / "summary.json").read_text()), json.loads((out_cli / "summary.json").read_text()))
    assert (out_py / "report.html").is_file()
    assert calls and calls[-1][0] == calls[-1][1], calls[-3:]
    df = r.to_pandas()
    assert list(df["hours"]) == [0.0, 250.0, 500.0]


def test_every_quantity_of_the_table_is_a_study_attribute_and_column(tmp):
    """The library's table of stage quantities is what the study exposes: every quantity an
    attribute (numpy array over the stages, equal to summary.json's values) and its columns
    those of stages.csv, with the dynamics', the flexible disc's and the losses' quantities
    present when they run."""
    cfg = write(tmp, "full.toml", short_text(dynamics=True, fem=True, lubrication=True))
    out = tmp / "full"
    r = rvlife.run_study(rvlife.Config.from_file(cfg), out=out)
    qs = rvlife.quantities()
    assert len(qs) >= 30 and len({q.name for q in qs}) == len(qs)
    header = (out / "stages.csv").read_text().splitlines()[0].split(",")
    assert header == [c for q in qs for c in q.columns]
    df = r.to_pandas()
    assert list(df.columns) == header
    for q in qs:
        v = getattr(r, q.name)
        assert isinstance(v, np.ndarray) and len(v) == 3, q.name
        assert q.name in dir(r)
        if len(q.columns) == 1:
            expected = [s[q.name] for s in r.stages]
            assert np.allclose(v, expected, rtol=0, atol=0), q.name
            assert np.allclose(df[q.name].to_numpy(), expected, rtol=0, atol=5e-7 * max(1.0, np.max(np.abs(expected)))), q.name
        assert q.unit in ("", "h", "um", "arcmin", "N", "MPa", "N m/arcmin", "N m", "W", "deg C"), q.unit
        assert q.models in ("static", "dynamics", "flexible", "lubrication")


def test_solves_release_the_gil():
    """While `te` runs in a thread, the main thread keeps running Python."""
    done = threading.Event()
    result = {}

    def work():
        # Solves for long enough that the main thread's loop can be counted (one `te` takes a
        # few milliseconds on a fast machine).
        for _ in range(30):
            result["te"] = rvlife.te(wear_um=10.0)
        done.set()

    t = threading.Thread(target=work)
    start = time.perf_counter()
    t.start()
    ticks = 0
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    elapsed = time.perf_counter() - start
    # With the GIL held for the whole solve the loop would run once or twice.
    assert ticks > 0.2 * elapsed / 0.001 * 0.5 and ticks > 10, (ticks, elapsed)
    assert result["te"].te_mean_arcmin > 0.0


# --- Monte Carlo and the Dask sweep -------------------------------------------------------------


def test_montecarlo_equals_cli(tmp):
    cfg = write(tmp, "mc.toml", mc_text())
    out_cli = tmp / "mc_cli"
    cli("montecarlo", cfg, "--samples", 8, "--seed", 7, "--out", out_cli)
    out_py = tmp / "mc_py"
    r = rvlife.montecarlo(rvlife.Config.from_file(cfg), samples=8, seed=7, out=out_py)
    for f in ("samples.csv", "stages.csv", "percentiles.csv", "summary.json"):
        assert (out_py / f).read_bytes() == (out_cli / f).read_bytes(), f
    import pandas as pd

    assert r.samples.equals(pd.read_csv(out_cli / "samples.csv"))
    assert r.out == out_py and r.summary is not None and "life" in r.summary
    assert len(repr(r)) < 200, repr(r)
    samples, stages = r.to_pandas()
    assert len(samples) == 8
    assert len(stages) == len((out_cli / "stages.csv").read_text().splitlines()) - 1


def test_dask_sweep_equals_the_serial_run(tmp):
    from dask.distributed import Client, LocalCluster

    cfg = write(tmp, "mc_sweep.toml", mc_text())
    c = rvlife.Config.from_file(cfg)
    serial = tmp / "mc_serial"
    rvlife.montecarlo(c, samples=8, seed=11, out=serial)
    swept = tmp / "mc_dask"
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            r = rvlife.sweep(rvlife.MonteCarlo(c, samples=8, seed=11), client, out=swept, tasks=4)
            # Studies in order, the same rows as in this process.
            texts = [short_text().replace("stage_hours = [0.0, 250.0, 500.0]", f"stage_hours = [0.0, {h}]") for h in (100.0, 300.0)]
            configs = [rvlife.Config.from_toml(t).replace({"wear.profile_update_hours": h / 2}) for t, h in zip(texts, (100.0, 300.0))]
            studies = rvlife.sweep(configs, client)
    for f in ("samples.csv", "stages.csv", "percentiles.csv", "summary.json", "config.toml"):
        assert (swept / f).read_bytes() == (serial / f).read_bytes(), f
    assert r.summary is not None and r.summary["plan"]["samples"] == 8
    assert list(studies["hours"]) == [0.0, 100.0, 0.0, 300.0]
    assert list(studies["wear.profile_update_hours"]) == [50.0, 50.0, 150.0, 150.0]
    local = rvlife.sweep(configs)
    assert studies.equals(local), (studies, local)


def test_dask_optimize_equals_the_local_search(tmp):
    """rvlife.optimize on a Dask cluster (each generation of NSGA-II sent to the workers at
    once, the problem built once per worker) finds the local search's candidates, byte for
    byte."""
    import pandas as pd
    from dask.distributed import Client, LocalCluster

    base = rvlife.Config.from_toml(short_text() + "\n[life]\nlost_motion_arcmin = 0.8\n")
    vary = {"cycloid.modification.equidistant_mm": (0.0, 0.006), "cycloid.eccentricity_mm": (1.25, 1.35)}
    args = dict(objective="life,max:torsional_stiffness_nm_per_arcmin@new", base=base, evaluations=12, seed=5)
    local = rvlife.optimize(vary, **args)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            dask = rvlife.optimize(vary, client=client, **args)
    assert len(local.candidates) == 12
    pd.testing.assert_frame_equal(local.candidates, dask.candidates)
    pd.testing.assert_frame_equal(local.pareto, dask.pareto)


# --- configs as values ----------------------------------------------------------------------


def test_replace_and_partial_dicts_edit_one_key_and_keep_the_rest():
    base = rvlife.example()
    c = base.replace({"cycloid.eccentricity_mm": 1.25, "errors.crank_phase_arcmin": [0.5, -0.5]})
    d0, d1 = base.to_dict(), c.to_dict()
    assert d1["cycloid"]["eccentricity_mm"] == 1.25 and d1["errors"]["crank_phase_arcmin"] == [0.5, -0.5]
    d1["cycloid"]["eccentricity_mm"] = d0["cycloid"]["eccentricity_mm"]
    del d1["errors"]
    assert d1 == d0
    # Comments are kept: every line but the edited one is the example's.
    import difflib

    diff = [x for x in difflib.ndiff(base.to_toml().splitlines(), c.to_toml().splitlines()) if x[:1] in "+-"]
    assert [x for x in diff if x.startswith("-")] == ["- eccentricity_mm = 1.3          # a"], diff
    assert [x for x in diff if x.startswith("+")] == [
        "+ eccentricity_mm = 1.25          # a", "+ ", "+ [errors]", "+ crank_phase_arcmin = [0.5, -0.5]"
    ], diff
    # A partial dict over the example is the same config; a keyword spelling too.
    assert rvlife.Config.from_dict({"cycloid": {"eccentricity_mm": 1.25}, "errors": {"crank_phase_arcmin": [0.5, -0.5]}}) == c
    assert base.replace(cycloid__eccentricity_mm=1.25) == base.replace({"cycloid.eccentricity_mm": 1.25})
    # An integer key stays an integer; None removes a key (its default applies).
    assert base.replace({"cycloid.pins": 40.0}) == base
    assert base.replace({"tolerances.rotation_arcmin": None}).get("tolerances.rotation_arcmin") is None
    assert c != base and len({c, base, base.replace({})}) == 2
    assert len(repr(c)) < 160 and "eccentricity_mm=1.25" in repr(c), repr(c)


def test_round_trips_through_dict_and_toml():
    for preset, _ in rvlife.presets():
        c = rvlife.example(preset)
        assert rvlife.Config.from_toml(c.to_toml()) == c, preset
        assert rvlife.Config.from_dict(c.to_dict(), base=c) == c, preset
    import pickle

    c = rvlife.example().replace({"cycloid.eccentricity_mm": 1.25})
    c2 = pickle.loads(pickle.dumps(c))
    assert c2 == c and c2.changes == c.changes


def test_bad_dotted_keys_raise_value_error_naming_them():
    base = rvlife.example()
    for key, value in [
        ("cycloid.eccentricty_mm", 1.2),
        ("nosuch.section", 1.0),
        ("cycloid.pins", "forty"),
        ("cycloid.pins.count", 3),
        ("Cycloid.Pins", 3),
    ]:
        with pytest.raises(ValueError, match=re.escape(key)):
            base.replace({key: value})
    with pytest.raises(ValueError, match=r"cycloid\.eccentricity_mm = -1\.2"):
        base.replace({"cycloid.eccentricity_mm": -1.2})
    with pytest.raises(ValueError, match=r"cycloid\.eccentricty_mm"):
        rvlife.Config.from_dict({"cycloid": {"eccentricty_mm": 1.2}})


def test_pairs_the_command_line_refuses_are_refused_naming_the_keywords(tmp):
    with pytest.raises(ValueError, match=r"wear_um.*hours"):
        rvlife.te(hours=100.0, wear_um=3.0)
    with pytest.raises(ValueError, match=r"wear_um.*hours"):
        rvlife.profile(hours=100.0, wear_um=3.0)
    with pytest.raises(ValueError, match=r"target_wear_um.*measured"):
        rvlife.calibrate(target_wear_um=30.0, measured=tmp / "m.csv")
    with pytest.raises(ValueError, match=r"fit_running_in.*measured"):
        rvlife.calibrate(fit_running_in=True)
    with pytest.raises(ValueError, match=r"force.*out"):
        rvlife.run_study(force=True)
    with pytest.raises(ValueError, match=r"samples"):
        rvlife.montecarlo(samples=-1)
    # The library's messages in Python's spelling: `force=True`, not `--force`.
    full = tmp / "full"
    full.mkdir(exist_ok=True)
    (full / "mine.txt").write_text("keep")
    with pytest.raises(ValueError) as e:
        rvlife.run_study(rvlife.Config.from_toml(short_text()), out=full)
    assert "out" in str(e.value) and "--" not in str(e.value), str(e.value)
    assert (full / "mine.txt").read_text() == "keep"


# --- typed results --------------------------------------------------------------------------


def declared(cls):
    return set(rvlife._results._fields(cls))


def test_result_attributes_are_declared_and_are_the_json_keys():
    """Each result class declares exactly the keys of its command's JSON (the attributes type
    checkers see), so neither can drift from the other."""
    cases = [
        (rvlife.ProfileResult, rvlife.profile(wear_um=5.0)),
        (rvlife.ContactResult, rvlife.contact(crank_deg=3.0, torque_nm=200.0)),
        (rvlife.TeResult, rvlife.te(wear_um=5.0, torque_nm=412.0)),
        (rvlife.HysteresisResult, rvlife.hysteresis(levels=3)),
        (rvlife.EfficiencyResult, rvlife.efficiency(speeds_rpm=[15.0], torques_nm=[412.0])),
        (rvlife.AccuracyLifeResult, rvlife.accuracy_life(rvlife.Config.from_toml(short_text() + MC_TOLERANCES))),
        (rvlife.ArchardFit, rvlife.calibrate(rvlife.Config.from_toml(short_text()), target_wear_um=20.0)),
    ]
    for cls, r in cases:
        assert isinstance(r, cls)
        assert declared(cls) == set(r.keys()), (cls.__name__, declared(cls) ^ set(r.keys()))
        for k in r.keys():
            assert getattr(r, k) is r[k], k
        assert len(repr(r)) < 300, repr(r)
    # The TE without a torque has no loaded keys: declared, None.
    r = rvlife.te(wear_um=5.0)
    assert declared(rvlife.TeResult) >= set(r.keys()) and r.loaded_te_arcmin is None


# --- every command against the command line -------------------------------------------------


MEASURED = """hours,lost_motion_arcmin,max_wear_um
0,,0
250,,{w1}
500,,{w2}
"""


def test_calibrate_equals_the_command_line(tmp):
    import pandas as pd

    cfg = write(tmp, "cal.toml", short_text())
    # In the test's folder: the command writes calibrated.toml where it runs.
    line = cli("calibrate", cfg, "--target-wear-um", 20, cwd=tmp)
    k_cli = float(line.split("=")[1].split()[0])
    fit = rvlife.calibrate(rvlife.Config.from_file(cfg), target_wear_um=20.0)
    assert abs(fit.archard_coefficient_mm3_per_n_m - k_cli) <= 5e-7 * k_cli, (fit, line)
    assert abs(fit.max_wear_um - 20.0) < 0.05
    # The fit to measurements: the same calibration.json, from a file or a DataFrame.
    w = rvlife.profile(rvlife.Config.from_file(cfg), hours=250.0).max_wear_um
    w2 = rvlife.profile(rvlife.Config.from_file(cfg), hours=500.0).max_wear_um
    data = write(tmp, "measured.csv", MEASURED.format(w1=1.1 * w, w2=1.05 * w2))
    out_cli = tmp / "cal_cli"
    cli("calibrate", cfg, "--measured", data, "--out", out_cli)
    out_py = tmp / "cal_py"
    r = rvlife.calibrate(rvlife.Config.from_file(cfg), measured=data, out=out_py)
    expected = json.loads((out_cli / "calibration.json").read_text())
    same(r.to_dict(), expected)
    assert (out_py / "calibration.json").read_bytes() == (out_cli / "calibration.json").read_bytes()
    r2 = rvlife.calibrate(rvlife.Config.from_file(cfg), measured=pd.read_csv(data))
    same(r2.to_dict(), expected)
    assert r.archard_coefficient_mm3_per_n_m["lower"] < r.archard_coefficient_mm3_per_n_m["value"]
    assert len(r.residuals_frame()) == r.points
    assert declared(rvlife.Calibration) >= set(r.keys())


def test_structure_calibration_equals_the_command_line(tmp):
    import pandas as pd

    # Frictionless, where the fit is exact to the grid's interpolation (with friction: the
    # library's own test, within 2 %).
    base = rvlife.example().replace({"lubrication.enabled": False})
    # A "bench" curve: the model's own hysteresis curve with 3 arcmin/(kN m) in series.
    stiff = base.replace({"reducer.structure.compliance_arcmin_per_knm": 3.0})
    h = rvlife.hysteresis(stiff)
    curve = pd.DataFrame({"torque_nm": h.torque_nm, "twist_arcmin": h.twist_arcmin})
    fit = rvlife.calibrate_structure(base, curve=curve)
    assert isinstance(fit, rvlife.StructureFit), fit
    c = fit.compliance_arcmin_per_knm
    # Noise-free, so the interval is narrow; the model's own curve is interpolated (24 levels).
    assert abs(c["value"] - 3.0) < 0.03 and c["lower"] < c["value"] < c["upper"], c
    assert fit.calibrated.get("reducer.structure.compliance_arcmin_per_knm") == round(c["value"], 4)
    # The same fit as the command line's calibration.json, from the same CSV file.
    data = tmp / "curve.csv"
    curve.to_csv(data, index=False)
    out_cli = tmp / "structure_cli"
    cli("calibrate", write(tmp, "base.toml", base.to_toml()), "--measured", data, "--out", out_cli)
    expected = json.loads((out_cli / "calibration.json").read_text())
    same(rvlife.calibrate_structure(base, curve=data).to_dict(), expected)
    assert declared(rvlife.StructureFit) >= set(expected.keys())
    # A catalogue b/a: the calibrated config gives it back within 2 %.
    cat = rvlife.calibrate_structure(base, catalogue_stiffness_nm_per_arcmin=108.0)
    b_a = rvlife.hysteresis(cat.calibrated).torsional_stiffness_nm_per_arcmin
    assert abs(b_a / 108.0 - 1.0) < 0.02, b_a
    with pytest.raises(ValueError, match="calibrate_structure"):
        rvlife.calibrate(base, measured=curve)
    with pytest.raises(ValueError, match="exactly one"):
        rvlife.calibrate_structure(base, curve=curve, catalogue_stiffness_nm_per_arcmin=108.0)


def test_merge_equals_the_command_line(tmp):
    cfg = write(tmp, "mc_merge.toml", mc_text())
    c = rvlife.Config.from_file(cfg)
    shards = []
    for i in (1, 2, 3):
        d = tmp / f"py_shard_{i}"
        rvlife.montecarlo(c, samples=6, seed=3, shard=f"{i}/3", out=d)
        shards.append(d)
    out_cli = tmp / "merged_cli"
    cli("merge", *shards, "--out", out_cli)
    out_py = tmp / "merged_py"
    r = rvlife.merge(shards, out_py)
    for f in ("samples.csv", "stages.csv", "percentiles.csv", "summary.json", "config.toml"):
        assert (out_py / f).read_bytes() == (out_cli / f).read_bytes(), f
    assert len(r.samples) == 6 and r.summary is not None


def test_accuracy_life_is_the_studys():
    c = rvlife.Config.from_toml(short_text(dynamics=True) + MC_TOLERANCES.replace("2.3", "0.9"))
    a = rvlife.accuracy_life(c)
    s = rvlife.run_study(c)
    assert s.accuracy_life is not None
    assert a.accuracy_life_h == s.accuracy_life.get("accuracy_life_h")
    assert a.limited_by == s.accuracy_life.get("limited_by") and a.verdict == s.verdict
    assert np.array_equal(a.lost_motion_arcmin, s.lost_motion_arcmin)


def test_progress_is_monotone_and_reaches_the_end(tmp):
    calls = []
    rvlife.montecarlo(rvlife.Config.from_toml(mc_text()), samples=12, seed=2, progress=lambda d, t: calls.append((d, t)))
    done = [d for d, _ in calls]
    assert done == sorted(done) and len(set(done)) == len(done) and done[-1] == 12, calls

    class Bar:
        def __init__(self):
            self.n, self.total, self.updates = 0, None, []

        def update(self, k):
            self.n += k
            self.updates.append(k)

        def refresh(self):
            pass

    bar = Bar()
    p = rvlife.tqdm_progress(bar)
    for d in (1, 3, 2, 3, 5):
        p(d, 5)
    assert bar.n == 5 and bar.updates == [1, 2, 2] and bar.total == 5


# --- design sweeps --------------------------------------------------------------------------


SWEEP_SETS = ["dynamics.enabled=false", "fem.enabled=false"]


def test_grid_and_sweep_equal_the_command_lines_sweep(tmp):
    import pandas as pd

    cfg = write(tmp, "sweep.toml", short_text() + "\n[life]\nlost_motion_arcmin = 0.8\n")
    base = rvlife.Config.from_file(cfg)
    axes = {"cycloid.eccentricity_mm": [1.25, 1.3], "cycloid.modification.equidistant_mm": [0.0, 0.004]}
    configs = rvlife.grid(axes, base)
    assert [c.changes["cycloid.eccentricity_mm"] for c in configs] == [1.25, 1.25, 1.3, 1.3]
    assert [c.get("cycloid.modification.equidistant_mm") for c in configs] == [0.0, 0.004, 0.0, 0.004]
    df = rvlife.sweep(configs)
    out = tmp / "sweep_cli"
    cli("sweep", cfg, "--vary", "cycloid.eccentricity_mm=1.25:1.3:2", "--vary",
        "cycloid.modification.equidistant_mm=0.0,0.004", "--out", out)
    ref = pd.read_csv(out / "sweep.csv")
    assert list(df.columns) == list(ref.columns)
    assert len(df) == len(ref) == 4 * 3
    for col in ref.columns:
        a, b = df[col], ref[col]
        if b.dtype.kind in "fi":
            assert np.allclose(a.to_numpy(float), b.to_numpy(float), rtol=0, atol=5e-6 * max(1.0, np.max(np.abs(np.nan_to_num(b.to_numpy(float))))), equal_nan=True), col
        else:
            assert [None if (isinstance(x, float) and math.isnan(x)) else x for x in a] == [None if (isinstance(x, float) and math.isnan(x)) else x for x in b], col
    for f in ("designs.csv", "summary.json", "report.html", "plots/accuracy_life.svg", "designs/design_3.toml"):
        assert (out / f).is_file(), f
    # A design's config is the study the sweep ran.
    one = rvlife.run_study(rvlife.Config.from_file(out / "designs" / "design_3.toml"))
    assert one.lost_motion_arcmin[-1] == pytest.approx(df[df.design == 3].lost_motion_arcmin.iloc[-1], abs=5e-6)
    with pytest.raises(ValueError, match=r"cycloid\.eccentricity_mm.*design 1"):
        rvlife.grid({"cycloid.eccentricity_mm": [1.3, -1.0]}, base)


def test_optimize_equals_the_command_lines_search(tmp):
    """rvlife.optimize runs the command line's search: the same candidates byte for byte
    (candidates.csv), the same with the same seed, the best feasible one no worse than the base
    design, its config the base with the keys set; a range out of the key's own range is refused
    naming the key before any study."""
    import pandas as pd

    cfg = write(tmp, "opt.toml", short_text() + "\n[life]\nlost_motion_arcmin = 0.8\n")
    base = rvlife.Config.from_file(cfg)
    vary = {"cycloid.modification.equidistant_mm": (0.0, 0.006), "cycloid.eccentricity_mm": (1.25, 1.35)}
    r = rvlife.optimize(vary, base=base, evaluations=8, seed=3)
    assert 1 <= len(r.candidates) <= 8
    assert r.start is not None and r.best is not None and r.optimum is not None
    assert r.best["life_score"] >= r.start["life_score"]
    assert r.optimum.get("cycloid.eccentricity_mm") == pytest.approx(r.best["cycloid.eccentricity_mm"], abs=1e-6)
    again = rvlife.optimize(vary, base=base, evaluations=8, seed=3)
    pd.testing.assert_frame_equal(r.candidates, again.candidates)
    out = tmp / "opt_cli"
    cli("optimize", cfg, "--vary", "cycloid.modification.equidistant_mm=0.0:0.006", "--vary",
        "cycloid.eccentricity_mm=1.25:1.35", "--evaluations", "8", "--seed", "3", "--out", out)
    ref = pd.read_csv(out / "candidates.csv")
    pd.testing.assert_frame_equal(r.candidates, ref)
    for f in ("pareto.csv", "optimum.toml", "summary.json", "report.html", "plots/convergence.svg"):
        assert (out / f).is_file(), f
    with pytest.raises(ValueError, match="cycloid.eccentricity_mm"):
        rvlife.optimize({"cycloid.eccentricity_mm": (-1.0, 1.3)}, base=base, evaluations=8)
