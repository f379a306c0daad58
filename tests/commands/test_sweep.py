"""`tvl sweep` through the real `tvl` process: every cell run once into one table whose rows
are what `tvl run --json` prints for them, a second sweep that goes on where the first
stopped, grids refused in one line, and the same rows from a Dask cluster's workers."""

from __future__ import annotations

import csv
import json
import re
import shutil
import subprocess
import sys
from dataclasses import fields
from pathlib import Path

import pytest
from conftest import TVL
from json_schemas import ENVELOPE, valid

from tvl_cli.commands.grid import COLUMNS
from tvl_cli.commands.workers import CLUSTER_EXTRA, dask_cluster
from tvl_cli.core.errors import BadInput
from tvl_cli.core.metrics import RunMetrics

SQUARE = Path(__file__).resolve().parents[2] / "worlds" / "square.txt"
# What `tvl run --json` prints: the metrics, then the contacts of each simulated minute.
PRINTED = [*(f.name for f in fields(RunMetrics)), "minutes"]
# One log (a world, a seed, a length of learning), two FAMs from it, two runs with each.
GRID = """\
world = "square"
seed = 2
config = ["single", "multi"]
learn_minutes = 1
behaviour = "wall-left"
threshold = [0.75, 0.9]
run_minutes = 0.5
"""
LOG = "logs/square-s2-m1.0.h5"
FAMS = ["fams/square-s2-m1.0-single.h5", "fams/square-s2-m1.0-multi.h5"]


def tvl(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([TVL, *map(str, args)], capture_output=True, text=True, timeout=120)


def sweep(*args: str | Path) -> dict:
    done = tvl("sweep", *args, "--json")
    assert done.returncode == 0, done.stderr
    assert done.stderr == ""  # no progress bar without a terminal
    return valid("sweep", done.stdout)


def journal(out: Path) -> list[dict]:
    return [json.loads(line) for line in (out / "results.jsonl").read_text().splitlines()]


@pytest.fixture(scope="module")
def swept(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The grid swept once on two local processes; its directory."""
    folder = tmp_path_factory.mktemp("sweep")
    (folder / "grid.toml").write_text(GRID)
    out = folder / "out"
    summary = sweep(folder / "grid.toml", "--out", out, "--workers", "2")
    assert summary["inputs"]["out"] == str(out) and summary["inputs"]["workers"] == 2
    assert summary["inputs"]["grid"]["path"] == str(folder / "grid.toml")
    assert (summary["cells"], summary["done"], summary["skipped"]) == (4, 4, 0)
    assert sorted(summary["outputs"]["files"]) == sorted(
        ["worlds/square.txt", LOG, *FAMS, "results.jsonl", "results.csv"]
    )
    return out


@pytest.mark.slow
def test_every_cell_is_a_row_of_its_grid_values_and_its_run_metrics(swept: Path) -> None:
    with open(swept / "results.csv", newline="") as table:
        rows = list(csv.DictReader(table))
    assert list(rows[0]) == ["kind", *COLUMNS, *PRINTED]
    assert [(r["config"], r["threshold"]) for r in rows] == [
        ("single", "0.75"), ("single", "0.9"), ("multi", "0.75"), ("multi", "0.9")
    ]  # fmt: skip
    for row in rows:
        assert (row["kind"], row["world"], row["seed"], row["learn_minutes"]) == (
            "tvl", "square", "2", "1.0"
        )  # fmt: skip
        assert (row["behaviour"], row["goal"], row["run_minutes"], row["reflexes"]) == (
            "wall-left", "", "0.5", "all"
        )  # fmt: skip
        assert float(row["sim_s"]) == 30.0
        assert [m["sim_s"] for m in json.loads(row["minutes"])] == [30.0]
    recorded = journal(swept)
    assert len(recorded) == 4
    assert all(list(row) == ["kind", *COLUMNS, *PRINTED] for row in recorded)


@pytest.mark.slow
def test_a_row_holds_what_tvl_run_prints_for_its_cell(swept: Path, tmp_path: Path) -> None:
    log, fam = tmp_path / "log.h5", tmp_path / "multi.h5"
    for command in (
        ("learn", SQUARE, "--log", log, "--minutes", "1", "--seed", "2"),
        ("train", log, "-o", fam, "--config", "multi"),
    ):
        assert tvl(*command).returncode == 0
    ran = tvl(
        "run", fam, SQUARE, "--behaviour", "wall-left", "--threshold", "0.9",
        "--minutes", "0.5", "--seed", "2", "--json",
    )  # fmt: skip
    assert ran.returncode == 0, ran.stderr
    printed = valid("run", ran.stdout)
    found = {key: value for key, value in printed.items() if key not in ENVELOPE}
    row = next(r for r in journal(swept) if (r["config"], r["threshold"]) == ("multi", 0.9))
    # The row names the cell's method as the grid does; the run's inputs record it whole.
    assert printed["inputs"]["method"]["preset"] == row["method"] == "default"
    assert row == {"kind": "tvl", **{column: row[column] for column in COLUMNS}, **found}
    assert printed["distance_m"] > 0


@pytest.mark.slow
def test_a_finished_sweep_runs_nothing_again(swept: Path) -> None:
    grid = swept.parent / "grid.toml"
    kept = {p: p.stat().st_mtime_ns for p in [swept / LOG, *(swept / f for f in FAMS)]}
    before = (swept / "results.jsonl").read_text()
    summary = sweep(grid, "--out", swept)
    files = summary["outputs"]["files"]
    assert (summary["done"], summary["skipped"], files) == (0, 4, ["results.csv"])
    printed = tvl("sweep", grid, "--out", swept, "--csv")
    assert printed.stdout == (swept / "results.csv").read_text()
    assert (swept / "results.jsonl").read_text() == before
    assert {p: p.stat().st_mtime_ns for p in kept} == kept


@pytest.mark.slow
def test_a_stopped_sweep_runs_only_the_cells_it_lacks(swept: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    shutil.copytree(swept, out)
    # As if killed while training the multi FAM, after the single FAM's runs had ended.
    rows = (out / "results.jsonl").read_text().splitlines(keepends=True)
    kept = [line for line in rows if json.loads(line)["config"] == "single"]
    (out / "results.jsonl").write_text("".join(kept))
    (out / FAMS[1]).unlink()
    summary = sweep(swept.parent / "grid.toml", "--out", out)
    assert (summary["done"], summary["skipped"]) == (2, 2)
    assert sorted(summary["outputs"]["files"]) == [FAMS[1], "results.csv", "results.jsonl"]
    assert (out / "results.csv").read_text() == (swept / "results.csv").read_text()


@pytest.mark.slow
def test_the_rows_draw_figure_21(swept: Path, tmp_path: Path) -> None:
    drawn = tvl("figure", "fig21", swept / "results.jsonl", "-o", tmp_path / "fig21.png")
    assert drawn.returncode == 0, drawn.stderr
    assert (tmp_path / "fig21.png").read_bytes().startswith(b"\x89PNG")


BASE = 'world = "square"\nseed = 1\nbehaviour = "avoid"\n'
BAD_GRIDS = {
    "an unknown key": (BASE + 'wrold = "square"\n', "unknown key 'wrold'"),
    "a value of the wrong type": (
        BASE + 'threshold = [0.8, "high"]\n',
        "'threshold' item 2 is 'high', expected a number",
    ),
    "a world file that is not there": (
        BASE.replace('"square"', '"nowhere.txt"'),
        "world 'nowhere.txt': no such world file",
    ),
    "a TOML syntax error": (BASE.replace("seed = 1", "seed = 1 2"), "grid.toml:2:"),
    "a key it must give": (BASE.replace('behaviour = "avoid"\n', ""), "no 'behaviour'"),
    "a reflex it does not know": (BASE + 'reflexes = "bumpy"\n', "reflexes 'bumpy' is not"),
    "a value given twice": (BASE.replace("seed = 1", "seed = [1, 1]"), "'seed' gives 1 twice"),
    "a goal and no goal run": (BASE + 'goal = "1.0,1.0"\n', "goal is for the goal behaviour"),
}


@pytest.mark.slow
@pytest.mark.parametrize("case", BAD_GRIDS)
def test_a_bad_grid_is_refused_in_one_line_before_anything_is_written(
    tmp_path: Path, case: str
) -> None:
    text, phrase = BAD_GRIDS[case]
    grid = tmp_path / "grid.toml"
    grid.write_text(text)
    refused = tvl("sweep", grid, "--out", tmp_path / "out")
    assert refused.returncode == 2, refused.stderr
    assert refused.stderr.count("\n") == 1 and refused.stderr.startswith(f"tvl: error: {grid}")
    assert phrase in refused.stderr, refused.stderr
    assert not (tmp_path / "out").exists()


def test_a_cluster_needs_dask(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "distributed", None)  # as if not installed
    needs = re.escape(f"--scheduler needs dask's distributed: {CLUSTER_EXTRA}")
    with pytest.raises(BadInput, match=needs), dask_cluster("tcp://127.0.0.1:8786"):
        pass


@pytest.mark.slow
def test_a_dask_clusters_workers_give_the_local_rows(swept: Path, tmp_path: Path) -> None:
    distributed = pytest.importorskip("distributed")
    out = tmp_path / "out"
    with distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=":0",  # any free port: 8787 may be taken
    ) as cluster:
        summary = sweep(
            swept.parent / "grid.toml", "--out", out, "--scheduler", cluster.scheduler_address
        )
    assert (summary["done"], summary["skipped"]) == (4, 0)
    assert (out / "results.csv").read_text() == (swept / "results.csv").read_text()
    assert sorted(journal(out), key=str) == sorted(journal(swept), key=str)
