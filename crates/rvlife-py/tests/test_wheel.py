"""The wheel (scripts/wheel) installs into a fresh virtual environment on a PATH without Rust
and runs the example. The wheel is `RVLIFE_WHEEL` (scripts/test builds it); without it the
test is skipped, unless `RVLIFE_REQUIRE_WHEEL=1` (CI) makes that a failure."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = """
import rvlife
r = rvlife.te(wear_um=10.0)
print("te_mean_arcmin", r.te_mean_arcmin)
a = rvlife.accuracy_life()
print(a.verdict)
"""


def test_the_wheel_installs_and_runs_without_rust(tmp_path):
    wheel = os.environ.get("RVLIFE_WHEEL")
    if not wheel:
        if os.environ.get("RVLIFE_REQUIRE_WHEEL") == "1":
            pytest.fail("RVLIFE_WHEEL is not set: scripts/test builds the wheel")
        pytest.skip("no wheel built (RVLIFE_WHEEL)")
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    # A PATH with the new environment and the system's programs only: no cargo, no rustc.
    path = f"{venv / 'bin'}:/usr/bin:/bin"
    assert shutil.which("cargo", path=path) is None and shutil.which("rustc", path=path) is None
    env = {"PATH": path, "HOME": os.environ.get("HOME", str(tmp_path)), "PIP_DISABLE_PIP_VERSION_CHECK": "1"}
    if "PIP_INDEX_URL" in os.environ:
        env["PIP_INDEX_URL"] = os.environ["PIP_INDEX_URL"]
    pip = subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "-q", wheel], env=env, capture_output=True, text=True)
    assert pip.returncode == 0, pip.stdout + pip.stderr
    run = subprocess.run([str(venv / "bin" / "python"), "-c", SCRIPT], env=env, capture_output=True, text=True, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert "te_mean_arcmin" in run.stdout and "accuracy life" in run.stdout, run.stdout
    name = Path(wheel).name
    assert "abi3" in name and "manylinux" in name, name
