"""Studies in the lab notebook (``docs/studies.md``): ``StudyResult.save`` writes
``LAB/studies/<name>/`` (summary JSON and the figure) and ``pendulab report --lab LAB`` shows
every study found there with its figure and statistics."""

import json
import math
import pathlib
import subprocess

import pytest

import pendulab as pl
from pendulab import study
from test_batch import lqr_gain

ROOT = pathlib.Path(__file__).resolve().parents[3]
CLI = ROOT / "target" / "release" / "pendulab"
needs_cli = pytest.mark.skipif(not CLI.exists(), reason="the CLI is built by tools/test's cargo step")

BOOK_K = {"kind": "state-feedback", "k_book": [3.16228, 13.47175, 4.48137, 2.26289]}


def test_save_writes_the_summary_and_the_figure(tmp_path):
    r = study.roa("cart", lqr_gain(), {"theta": (-1.0, 1.0, 7), "dtheta": (-2.0, 2.0, 5)}, 1.0)
    folder = pathlib.Path(r.save(tmp_path, name="roa-small"))
    assert folder == tmp_path / "studies" / "roa-small"
    s = json.loads((folder / "summary.json").read_text())
    assert s["kind"] == "roa" and s["key"] == r.study.key and s["figure"] == "figure.svg"
    assert s["spec"] == {**r.study.spec, "travel": "inf"} and s["pendulab_version"] == pl.__version__
    assert s["stats"] == r.stats
    assert (folder / "figure.svg").read_text().lstrip().startswith("<")
    assert sorted(p.name for p in folder.iterdir()) == ["figure.svg", "summary.json"]  # no leftovers
    with pytest.raises(pl.InvalidArgumentError, match="plain folder name"):
        r.save(tmp_path, name="../x")


@needs_cli
def test_the_lab_report_shows_every_saved_study(tmp_path):
    lab = tmp_path / "lab"
    subprocess.run([str(CLI), "lab", "init", str(lab), "--plant", "cart"], check=True, capture_output=True)
    roa = study.roa("cart", lqr_gain(), {"theta": (-1.0, 1.0, 7), "dtheta": (-2.0, 2.0, 5)}, 1.0)
    roa.save(lab, name="roa-lqr")
    # A Monte Carlo study whose runs all fall: NaN statistics are written as null, shown as a dash.
    mc = study.monte_carlo("cart", BOOK_K, {"m_p": ("uniform", 0.09, 0.11)}, {"saturation": True}, 4, seed=2,
                           x0=(0.0, 0.9, 0.0, 0.0), duration=1.0)
    assert math.isnan(mc.stats["settling_time_mean"])
    mc.save(lab, name="mc-falls", field="peak_input")
    out = tmp_path / "report"
    subprocess.run([str(CLI), "report", "--lab", str(lab), "--out", str(out)], check=True, capture_output=True)
    page = (out / "index.html").read_text()
    assert '<h2 id="studies">Studies</h2>' in page
    for name, kind in (("mc-falls", "Monte Carlo"), ("roa-lqr", "region of attraction")):
        assert f'<h3 id="study-{name}">{name}</h3>' in page
        assert f"<p>{kind} study (pendulab {pl.__version__}).</p>" in page
        assert (out / "figures" / f"study-{name}.svg").stat().st_size > 0
    assert page.index("study-mc-falls") < page.index("study-roa-lqr")  # name order
    assert f"<tr><td>caught</td><td>{roa.stats['caught']}</td></tr>" in page
    assert "<tr><td>settling_time_mean</td><td>—</td></tr>" in page
