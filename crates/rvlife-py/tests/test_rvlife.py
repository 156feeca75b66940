"""The Python package against the command line: same validation, same numbers, the Dask sweep
equal to the serial Monte Carlo run. The command line binary is `RVLIFE_BIN` or the workspace's
`target/release/rvlife`."""

import json
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


def short_text(dynamics=False, fem=False):
    """The example with three stages (0, 250, 500 h); the dynamic model (0.15 s) and the FE disc
    when asked."""
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
    those of stages.csv, with the dynamics' and the flexible disc's quantities present when
    they run."""
    cfg = write(tmp, "full.toml", short_text(dynamics=True, fem=True))
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
        assert q.unit in ("", "h", "um", "arcmin", "N", "MPa", "N m/arcmin"), q.unit
        assert q.models in ("static", "dynamics", "flexible")


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
    assert r.samples_csv == (out_cli / "samples.csv").read_text()
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
            # Studies in order.
            texts = [short_text().replace("stage_hours = [0.0, 250.0, 500.0]", f"stage_hours = [0.0, {h}]") for h in (100.0, 300.0)]
            studies = rvlife.sweep([rvlife.Config.from_toml(t) for t in texts], client)
    for f in ("samples.csv", "stages.csv", "percentiles.csv", "summary.json", "config.toml"):
        assert (swept / f).read_bytes() == (serial / f).read_bytes(), f
    assert r.summary["plan"]["samples"] == 8
    assert [s.stages[-1]["hours"] for s in studies] == [100.0, 300.0]
    one = rvlife.run_study(rvlife.Config.from_toml(texts[1]))
    same(studies[1].to_dict(), one.to_dict())
