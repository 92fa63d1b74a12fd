"""The tutorial notebook runs top to bottom (nbclient, a fresh ipykernel, matplotlib's Agg
backend, no network), from the repository's root as its text says."""

import pathlib

import pytest

nbformat = pytest.importorskip("nbformat", reason="pinned in requirements-test.txt")
nbclient = pytest.importorskip("nbclient", reason="pinned in requirements-test.txt")

ROOT = pathlib.Path(__file__).resolve().parents[3]
NOTEBOOK = ROOT / "crates" / "python" / "notebooks" / "tutorial.ipynb"


def test_tutorial_runs_top_to_bottom():
    nb = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(
        nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(ROOT)}}
    )
    client.execute()  # raises CellExecutionError naming the cell on any error
    texts = [o.get("text", "") for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    # The last cell's rollout: the LQR on the identified model holds the whole episode.
    assert any(t.strip() == "return 500.0" for t in texts), texts[-3:]
    assert (ROOT / "target" / "tutorial" / "servo.png").stat().st_size > 0
