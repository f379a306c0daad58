"""`tvl sweep` through the real `tvl` process: every cell run once into one table whose rows
are what `tvl run --json` prints for them, a second sweep that goes on where the first
stopped, grids refused in one line, and the same rows from a Dask cluster's workers."""

from __future__ import annotations

import csv
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import fields
from pathlib import Path

import pytest
from conftest import TVL
from json_schemas import ENVELOPE, valid

from tvl_cli.core.errors import BadInput
from tvl_cli.core.method import DEFAULT, reflexes_text
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.sweep.cell import COLUMNS
from tvl_cli.sweep.executors import CLUSTER_EXTRA, dask_cluster
from tvl_cli.sweep.layout import learning_tag
from tvl_cli.sweep.runner import WORK_DIGEST

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
# Named for the method they were learnt by (ours here), whatever the default is that day.
OURS = learning_tag(DEFAULT)
LOG = f"logs/square-s2-m1.0{OURS}.h5"
FAMS = [f"fams/square-s2-m1.0{OURS}-single.h5", f"fams/square-s2-m1.0{OURS}-multi.h5"]


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
    # The CSV's columns: the grid's values, what ran them, and the run metrics; each run's
    # per-minute records, a table of their own, are in results.jsonl.
    assert list(rows[0]) == [*COLUMNS, WORK_DIGEST, *PRINTED[:-1]]
    assert [(r["config"], r["threshold"]) for r in rows] == [
        ("single", "0.75"), ("single", "0.9"), ("multi", "0.75"), ("multi", "0.9")
    ]  # fmt: skip
    for row in rows:
        assert (row["kind"], row["world"], row["seed"], row["learn_minutes"]) == (
            "tvl", "square", "2", "1"
        )  # fmt: skip
        assert (row["behaviour"], row["goal"], row["run_minutes"], row["reflexes"]) == (
            "wall-left", "", "0.5", reflexes_text(DEFAULT.reflexes)
        )  # fmt: skip
        assert float(row["sim_s"]) == 30.0 and row["goal_reached"] == ""  # no goal sought
    recorded = journal(swept)
    assert len(recorded) == 4
    assert all([m["sim_s"] for m in row["minutes"]] == [30.0] for row in recorded)
    assert all(list(row) == [*COLUMNS, WORK_DIGEST, *PRINTED] for row in recorded)
    assert len({row[WORK_DIGEST] for row in recorded}) == 2  # one method, two configurations


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
    # All but how the run ended: a sweep's run is never stopped part way (a signal stops the
    # sweep, and the cell runs again when it goes on).
    assert printed["status"] == "finished"
    found = {key: value for key, value in printed.items() if key not in {*ENVELOPE, "status"}}
    row = next(r for r in journal(swept) if (r["config"], r["threshold"]) == ("multi", 0.9))
    # The row names the cell's method as the grid does; the run's inputs record it whole.
    assert printed["inputs"]["method"]["preset"] == row["method"] == "default"
    grid_values = {column: row[column] for column in (*COLUMNS, WORK_DIGEST)}
    assert row == {"kind": "tvl", **grid_values, **found}
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
def test_a_sweep_runs_again_the_cells_whose_method_changed(tmp_path: Path) -> None:
    # A grid's method file edited after a sweep, in a field no grid column holds: its cells
    # run again by the method as it is now, learning and training anew, rather than read
    # back as they ran (their grid values are the same).
    (tmp_path / "mine.toml").write_text("margin_m = 0.1\n")
    grid = tmp_path / "grid.toml"
    grid.write_text(GRID.replace('["single", "multi"]', '"single"') + 'method = "mine.toml"\n')
    out = tmp_path / "out"
    first = sweep(grid, "--out", out)
    (tmp_path / "mine.toml").write_text("margin_m = 0.12\n")
    again = sweep(grid, "--out", out)
    assert (first["done"], again["done"], again["skipped"]) == (2, 2, 0)
    assert (first["redone"], again["redone"]) == (0, 2)
    learnt = [name for name in again["outputs"]["files"] if name.startswith(("logs/", "fams/"))]
    assert len(learnt) == 2  # a log and a FAM by the method as it is now
    rows = journal(out)
    assert len(rows) == 4 and len({row[WORK_DIGEST] for row in rows}) == 2
    assert {row["threshold"] for row in rows} == {0.75, 0.9}  # the same grid values twice
    # The same method once more: nothing runs.
    assert sweep(grid, "--out", out)["skipped"] == 2


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
    "a key it must give": (BASE.replace("seed = 1\n", ""), "no 'seed'"),
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


def with_seed_three(swept: Path, out: Path) -> Path:
    """A copy of the swept directory whose journal holds the cells of a second seed too, as
    if swept already, each run a little faster and with a contact more a minute than seed
    2's; the grid of both seeds."""
    shutil.copytree(swept, out)
    rows = journal(out)
    more = [
        {
            **row,
            "seed": 3,
            "mean_speed_mps": row["mean_speed_mps"] + 0.02,
            "contacts_per_min": row["contacts_per_min"] + 1.0,
        }
        for row in rows
    ]
    with open(out / "results.jsonl", "a") as journal_file:
        journal_file.writelines(json.dumps(row) + "\n" for row in more)
    grid = out.parent / "two-seeds.toml"
    grid.write_text(GRID.replace("seed = 2", "seed = [2, 3]"))
    return grid


@pytest.mark.slow
def test_the_terminal_shows_each_settings_mean_and_interval_over_seeds(
    swept: Path, tmp_path: Path
) -> None:
    out = tmp_path / "out"
    grid = with_seed_three(swept, out)
    shown = tvl("sweep", grid, "--out", out)
    assert shown.returncode == 0, shown.stderr
    lines = shown.stdout.splitlines()
    assert lines[0].startswith("8 cells: 0 run now, 8 done before; the table is")
    assert str(out / "results.csv") in shown.stdout.replace("\n", "")  # folded, not cut
    assert max(map(len, lines)) <= 80  # a terminal's width when there is none
    assert "mean ± 95 % interval over seeds (Student's t)" in shown.stdout
    for row in (r for r in journal(swept) if r["config"] == "multi"):
        speed = row["mean_speed_mps"] + 0.01  # the mean of seeds 2 and 3
        # Two seeds 0.02 apart: a standard error of 0.01, and t of one degree of freedom.
        speed_text = f"{speed:.3f} ± {12.706205 * 0.01:.3f}"
        # Contacts a minute half a contact about their mean: ± 6.35, which would reach below
        # 0, so the interval stops there (a contact rate is never negative).
        contacts, half = row["contacts_per_min"] + 0.5, 12.706205 * 0.5
        assert contacts < half
        contacts_text = f"{contacts:.2f} (0.00–{contacts + half:.2f})"
        line = next(line for line in lines if f"│ multi  │ {row['threshold']:<9g} │" in line)
        assert [cell.strip() for cell in line.split("│")[3:6]] == ["2", contacts_text, speed_text]


@pytest.mark.slow
def test_a_plot_of_the_sweep_is_drawn_beside_its_table_or_where_asked(
    swept: Path, tmp_path: Path
) -> None:
    out = tmp_path / "out"
    grid = with_seed_three(swept, out)
    summary = sweep(grid, "--out", out, "--plot", "x=threshold,y=mean_speed_mps,hue=config")
    beside = out / "mean_speed_mps-by-threshold-config.png"
    assert summary["outputs"]["plot"] == str(beside)
    assert beside.read_bytes().startswith(b"\x89PNG")
    picture = tmp_path / "speed.svg"
    drawn = sweep(grid, "--out", out, "--plot", "x=config,y=contacts_per_min", "-o", picture)
    assert drawn["outputs"]["plot"] == str(picture)
    assert picture.read_bytes().startswith(b"<?xml")
    assert (drawn["done"], drawn["skipped"]) == (0, 8)
    again = ("sweep", grid, "--out", out, "--plot", "x=world,y=distance_m", "-o", picture)
    before = picture.read_bytes()
    kept = tvl(*again)
    assert (kept.returncode, kept.stderr) == (
        2, f"tvl: error: {picture}: already exists (use --force to overwrite)\n"
    )  # fmt: skip
    assert picture.read_bytes() == before
    assert sweep(*again[1:], "--force")["outputs"]["plot"] == str(picture)
    assert picture.read_bytes() != before


@pytest.mark.slow
def test_a_killed_sweep_leaves_a_lock_the_next_one_takes_over(swept: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    grid = swept.parent / "grid.toml"
    # Its own session, so that its worker processes are killed with it.
    first = subprocess.Popen(
        [TVL, "sweep", grid, "--out", out, "--json"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    try:
        wait_for(lambda: any((out / "logs").glob("*")))  # learning has begun
        second = tvl("sweep", grid, "--out", out)
        assert second.returncode == 2
        assert second.stderr == (
            f"tvl: error: {out.absolute() / 'results.jsonl'}: locked by another tvl sweep in "
            f"this directory (pid {first.pid})\n"
        )
    finally:
        os.killpg(first.pid, signal.SIGKILL)
        first.wait()
    assert (out / "results.jsonl.lock").read_text() == f"{first.pid}\n"  # left behind
    summary = sweep(grid, "--out", out)
    assert summary["done"] + summary["skipped"] == 4  # the runs that ended before the kill kept
    assert len(journal(out)) == 4  # each cell once
    assert (out / "results.csv").read_text() == (swept / "results.csv").read_text()
    assert not (out / "results.jsonl.lock").exists()


@pytest.mark.slow
def test_a_local_cluster_shows_its_dashboard_and_outlives_its_workers(
    swept: Path, tmp_path: Path
) -> None:
    psutil = pytest.importorskip("psutil")
    pytest.importorskip("distributed")
    out = tmp_path / "out"
    running = subprocess.Popen(
        [TVL, "sweep", swept.parent / "grid.toml", "--out", out, "--scheduler", "local:2"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        wait_for(lambda: any((out / "logs").glob("*")))  # a worker is learning
        # Every worker process, the one learning among them, killed as if its machine died.
        children = psutil.Process(running.pid).children(recursive=True)
        workers = [child for child in children if "spawn_main" in " ".join(child.cmdline())]
        assert len(workers) == 2
        for worker in workers:
            worker.kill()
        stdout, stderr = running.communicate(timeout=300)
    finally:
        running.kill()
        running.wait()
    assert running.returncode == 0, stderr
    assert re.search(r"^dashboard: http://127\.0\.0\.1:\d+/status$", stderr, re.MULTILINE)
    assert "Traceback" not in stderr
    assert stdout.startswith("4 cells: 4 run now, 0 done before")
    assert (out / "results.csv").read_text() == (swept / "results.csv").read_text()


def wait_for(condition: Callable[[], bool], timeout_s: float = 120.0) -> None:
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert time.monotonic() < deadline, "waited too long"
        time.sleep(0.05)
