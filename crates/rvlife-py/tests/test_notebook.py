"""The example notebook (examples/design_study.ipynb) executes from top to bottom, so what it
shows stays true."""

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]


def test_the_design_study_notebook_executes(tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    nb = nbformat.read(ROOT / "examples" / "design_study.ipynb", as_version=4)
    client = nbclient.NotebookClient(nb, timeout=900, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}})
    client.execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    assert not [o for o in outputs if o.get("output_type") == "error"]
    text = "".join(o.get("text", "") for o in outputs)
    assert "accuracy life" in text or "within spec" in text, text[-500:]
