"""pendulab.book: the registry and the examples' values equal the CLI's (``pendulab book list``
and ``pendulab book run ID --json``: one code path), figures are written where asked, the
report is written, and an unknown id raises."""

import json
import pathlib
import subprocess

import numpy as np
import pytest

import pendulab as pl
from pendulab import book

ROOT = pathlib.Path(__file__).resolve().parents[3]
CLI = ROOT / "target" / "release" / "pendulab"
needs_cli = pytest.mark.skipif(not CLI.exists(), reason="the CLI is built by tools/test's cargo step")


def cli_json(*args):
    out = subprocess.run([str(CLI), *args], check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def as_json_value(v):
    """A Python value in the CLI's JSON form (complex as [re, im] pairs)."""
    if isinstance(v, np.ndarray) and np.iscomplexobj(v):
        return [[z.real, z.imag] for z in v]
    if isinstance(v, np.ndarray):
        return v.tolist()
    return v


@needs_cli
def test_list_equals_the_cli():
    out = subprocess.run(
        [str(CLI), "book", "list", "--json"], check=True, capture_output=True, text=True
    ).stdout
    cli_ids = [json.loads(line)["id"] for line in out.splitlines() if line.strip()]
    assert book.ids() == cli_ids
    assert all(e["section"] for e in book.list())


@needs_cli
@pytest.mark.parametrize(
    "id",
    ["p1c43_stability2", "p1c511_ex1", "p1c523_ex8_adip_lqr", "p2c112_ex1_alpha_stability", "p1c322_cdip_id_least_square"],
)
def test_run_equals_the_cli(id):
    res = book.run(id)
    cli = cli_json("book", "run", id, "--json")
    assert {k: as_json_value(v) for k, v in res["values"].items()} == cli["values"]
    assert res["id"] == id and res["figures"] == []


def test_figures_are_written_where_asked(tmp_path):
    res = book.run("p1c43_stability1", out=tmp_path)
    assert res["figures"]
    for f in res["figures"]:
        p = pathlib.Path(f)
        assert p.parent == tmp_path and p.stat().st_size > 0
    pngs = [p for p in map(pathlib.Path, res["figures"]) if p.suffix == ".png"]
    assert pngs and pngs[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_references_are_compared():
    res = book.run("p2c121_ex3_alpha_stability_opt")
    refs = {r["name"]: r for r in res["references"]}
    # Book Part 2 example 1.3 prints the optimum 2.929.
    assert refs["optimum"]["value"] == 2.929
    assert refs["optimum"]["reproduced"] == (abs(res["values"]["optimum"] - 2.929) <= refs["optimum"]["tolerance"])
    assert res["status"] in ("reproduced", "agrees where compared", "differs from book")


def test_report_writes_the_page(tmp_path):
    ids = ["p1c43_stability1", "p1c511_ex1"]
    r = book.report(tmp_path, only=ids)
    assert pathlib.Path(r["index"]).exists()
    assert r["total"] == 2 and r["failing"] == 0 and r["failing_ids"] == []
    counts = ("reproduced", "partly_compared", "runs", "differs", "needs_data", "failing")
    assert sum(r[k] for k in counts) == r["total"]
    table = (tmp_path / "status.md").read_text()
    assert all(i in table for i in ids)
    assert any((tmp_path / "figures" / "p1c43_stability1").iterdir())


def test_unknown_id_raises():
    with pytest.raises(pl.InvalidArgumentError, match="no_such_example"):
        book.run("no_such_example")
    with pytest.raises(pl.InvalidArgumentError):
        book.report("/tmp/unused", only=["no_such_example"])
