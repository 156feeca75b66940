"""Type checkers see the results' attributes: ``mypy --strict`` passes on a script that uses
them (``typed/use_results.py``), and fails on one that reads an attribute no result has."""

import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent


def mypy(path):
    pytest.importorskip("mypy")
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental", "--cache-dir", "/dev/null", str(path)],
        capture_output=True,
        text=True,
    )


def test_mypy_strict_passes_on_a_script_using_the_results():
    o = mypy(HERE / "typed" / "use_results.py")
    assert o.returncode == 0, o.stdout + o.stderr


def test_mypy_strict_catches_a_misspelt_attribute(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text("import rvlife\n\nx: float = rvlife.te().te_mean_arcmn\n")
    o = mypy(bad)
    assert o.returncode == 1 and "te_mean_arcmn" in o.stdout, o.stdout + o.stderr
