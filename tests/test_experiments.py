"""The experiments: each grid of experiments/grids/ at its sizes, run at its tiny size through
the real `tvl sweep` and drawn by the real `tvl figure`; and `tvl figure`'s refusals."""

from __future__ import annotations

import json
import subprocess
from collections.abc import Callable
from dataclasses import asdict, fields
from pathlib import Path
from typing import Any, NamedTuple

import pytest
from click.testing import CliRunner
from conftest import TVL
from json_schemas import valid

from tvl_cli.analysis.time_to_competence import is_competent, time_to_competence
from tvl_cli.cli.main import main
from tvl_cli.core.competence import COMPETENCE_RUN_MINUTES
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.sweep.cell import COLUMNS
from tvl_cli.sweep.grid import FULL, QUICK, SIZES, TINY, read_grid

GRIDS = Path(__file__).resolve().parent.parent / "experiments" / "grids"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
METRICS = {f.name for f in fields(RunMetrics)}
# Each grid, the figure `tvl figure` draws of it (None: the sweep's own table is its
# result), and the kinds of cell it runs.
EXPERIMENTS: dict[str, tuple[str | None, set[str]]] = {
    "fig19": ("fig19", {"learn", "tvl", "dwa", "qlearn"}),
    "fig21": ("fig21", {"tvl"}),
    "fig22": ("fig22", {"tvl", "dwa"}),
    "fig24": ("fig24", {"learn", "tvl", "dwa", "qlearn"}),
    "fig27": ("fig27", {"tvl", "dwa"}),
    "ablation": ("ablation", {"tvl"}),
    "online": ("online", {"tvl"}),
    "exploration": ("exploration", {"learn", "tvl"}),
    "design_inputs": (None, {"tvl"}),
}
# The paper's figures: each shows ours and the paper's method side by side.
PAPER_FIGURES = ("fig19", "fig21", "fig22", "fig24", "fig27")
# The grids whose avoid runs judge competence: at full size, each as long as the test's.
JUDGE_COMPETENCE = ("fig19", "fig24", "exploration")


def test_every_grid_file_is_an_experiment_here() -> None:
    assert {path.stem for path in GRIDS.glob("*.toml")} == set(EXPERIMENTS)


@pytest.mark.slow  # over a second
@pytest.mark.parametrize("name", sorted(EXPERIMENTS))
def test_each_grid_is_smaller_at_each_smaller_size(name: str) -> None:
    cells = {size: read_grid(GRIDS / f"{name}.toml", None, size).cells for size in SIZES}
    assert len(cells[TINY]) < len(cells[QUICK]) < len(cells[FULL])
    assert {cell.kind for cell in cells[TINY]} == EXPERIMENTS[name][1]


@pytest.mark.parametrize("name", PAPER_FIGURES)
def test_a_paper_figure_runs_five_trials_of_ours_and_of_the_papers_method(name: str) -> None:
    cells = read_grid(GRIDS / f"{name}.toml").cells
    tvl = [cell for cell in cells if cell.kind == "tvl"]
    assert {cell.seed for cell in cells} == {1, 2, 3, 4, 5}
    assert {cell.method for cell in tvl} == {"default", "paper"}
    # Each method runs the same settings.
    ours = {(c.world, c.seed, c.config, c.minute, c.behaviour, c.goal) for c in tvl}
    for method in ("default", "paper"):
        assert {
            (c.world, c.seed, c.config, c.minute, c.behaviour, c.goal)
            for c in tvl
            if c.method == method
        } == ours


@pytest.mark.parametrize("name", JUDGE_COMPETENCE)
def test_competence_is_judged_by_runs_of_the_defined_length(name: str) -> None:
    cells = read_grid(GRIDS / f"{name}.toml").cells
    assert {c.run_minutes for c in cells if c.behaviour == "avoid"} == {COMPETENCE_RUN_MINUTES}


# --- each grid at its tiny size, through the real commands --------------------------------


class Swept(NamedTuple):
    out: Path  # the sweep's directory
    summary: dict[str, Any]  # what `tvl sweep --json` printed


def tvl(*args: object) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [TVL, *map(str, args)], capture_output=True, text=True, timeout=300, check=False
    )


def sweep_tiny(name: str, out: Path) -> subprocess.CompletedProcess[str]:
    return tvl("sweep", GRIDS / f"{name}.toml", "--size", "tiny", "--out", out, "--json")


@pytest.fixture(scope="module")
def tiny(tmp_path_factory: pytest.TempPathFactory) -> Callable[[str], Swept]:
    """Each grid swept at its tiny size once, shared by the tests of this module."""
    swept: dict[str, Swept] = {}

    def get(name: str) -> Swept:
        if name not in swept:
            out = tmp_path_factory.mktemp(name) / "out"
            done = sweep_tiny(name, out)
            assert done.returncode == 0, done.stderr
            swept[name] = Swept(out, json.loads(done.stdout))
        return swept[name]

    return get


def rows_of(out: Path) -> list[dict[str, Any]]:
    return [json.loads(line) for line in (out / "results.jsonl").read_text().splitlines()]


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(EXPERIMENTS))
def test_a_tiny_sweep_writes_a_row_of_each_cell_with_what_its_figure_reads(tiny, name):
    out, summary = tiny(name)
    rows = rows_of(out)
    cells = read_grid(GRIDS / f"{name}.toml", None, TINY).cells
    assert summary["cells"] == summary["done"] == len(rows) == len(cells)
    assert summary["inputs"]["size"] == "tiny"
    assert {row["kind"] for row in rows} == EXPERIMENTS[name][1]
    for row in rows:
        assert set(COLUMNS) <= row.keys()
        if row["kind"] in ("tvl", "dwa", "qlearn"):
            assert row.keys() >= METRICS
        if row["kind"] == "learn":
            assert {"minute", "delta_v", "collisions", "coverage"} <= row["minutes"][0].keys()
        if row["kind"] == "qlearn":
            assert {"learn_collisions", "learn_minutes"} <= row.keys()
        if row["trace"]:
            assert (out / row["trace_file"]).is_file()


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(n for n, (figure, _) in EXPERIMENTS.items() if figure))
def test_a_tiny_sweep_draws_its_figure_and_table(tiny, name, tmp_path):
    figure = EXPERIMENTS[name][0]
    png, table = tmp_path / f"{name}.png", tmp_path / f"{name}.md"
    drawn = tvl("figure", figure, tiny(name).out / "results.jsonl", "-o", png, "--table", table)
    assert drawn.returncode == 0, drawn.stderr
    assert png.read_bytes().startswith(PNG_MAGIC)
    text = table.read_text()
    assert text.startswith("### ") and "| --- |" in text
    if name in PAPER_FIGURES:
        assert "ours" in text and "paper's method" in text


@pytest.mark.slow
def test_a_finished_sweep_run_again_does_nothing(tiny):
    out, first = tiny("fig24")
    before = (out / "results.jsonl").read_bytes()
    again = sweep_tiny("fig24", out)
    assert again.returncode == 0, again.stderr
    summary = json.loads(again.stdout)
    assert (summary["done"], summary["skipped"]) == (0, first["cells"])
    assert (out / "results.jsonl").read_bytes() == before


@pytest.mark.slow
def test_figure_json_names_its_files_and_carries_the_table(tiny, tmp_path):
    results = tiny("fig21").out / "results.jsonl"
    png, table = tmp_path / "f.png", tmp_path / "f.md"
    result = tvl("figure", "fig21", results, "-o", png, "--table", table, "--json")
    assert result.returncode == 0, result.stderr
    printed = valid("figure", result.stdout)
    assert printed["inputs"]["figure"] == "fig21"
    assert printed["inputs"]["results"]["path"] == str(results)
    assert printed["outputs"] == {"picture": str(png), "table": str(table)}
    assert printed["summary_markdown"] == table.read_text()
    assert png.read_bytes().startswith(PNG_MAGIC)


# --- competence, and `tvl figure`'s refusals, in-process ---------------------------------


def avoid_run(minute: float, contacts_per_min: float, speed_mps: float) -> dict[str, object]:
    """A snapshot's avoid run as a results line holds it; its contacts all near misses."""
    contacts = round(contacts_per_min * 5)
    metrics = RunMetrics(
        sim_s=300.0,
        distance_m=300.0 * speed_mps,
        mean_speed_mps=speed_mps,
        mean_drive_speed_mps=speed_mps,
        collisions=0,
        near_misses=contacts,
        contacts=contacts,
        contacts_per_min=contacts_per_min,
        collisions_per_min=0.0,
        backoffs=contacts,
        spins=0,
        trapped=0,
        mean_clearance_m=0.3,
        mean_wall_clearance_m=None,
        goal_reached=False,
        time_to_goal_s=None,
    )
    return {"kind": "tvl", "minute": minute, **asdict(metrics)}


def test_competence_needs_few_contacts_and_enough_speed_limits_included():
    assert is_competent(avoid_run(1, 0.2, 0.3))
    assert not is_competent(avoid_run(1, 0.21, 0.5))
    assert not is_competent(avoid_run(1, 0.0, 0.29))


def test_time_to_competence_is_the_first_competent_snapshot_minute():
    runs = [avoid_run(6, 0.0, 0.4), avoid_run(3, 0.1, 0.35), avoid_run(4, 1.0, 0.4)]
    assert time_to_competence(runs) == 3
    assert time_to_competence([avoid_run(5, 0.4, 0.5)]) is None


def figure(*args: object) -> tuple[int, str]:
    done = CliRunner().invoke(main, ["figure", *map(str, args)])
    return done.exit_code, done.stderr


def test_figure_names_the_line_that_is_not_json(tmp_path):
    results = tmp_path / "results.jsonl"
    results.write_text('{"kind": "tvl"}\n{"kind": \n')
    code, stderr = figure("fig21", results, "-o", tmp_path / "f.png")
    assert code == 2
    assert stderr.startswith(f"tvl: error: {results}:2:")
    assert not (tmp_path / "f.png").exists()


def test_figure_refuses_an_unknown_name(tmp_path):
    results = tmp_path / "results.jsonl"
    results.write_text('{"kind": "tvl"}\n')
    code, stderr = figure("fig99", results, "-o", tmp_path / "f.png")
    assert code == 2
    assert "unknown figure 'fig99'" in stderr


@pytest.mark.parametrize(
    "name", ["fig19", "fig21", "fig22", "fig24", "fig27", "ablation", "online", "exploration"]
)
def test_figure_refuses_results_without_the_runs_it_draws(tmp_path, name):
    results = tmp_path / "results.jsonl"
    results.write_text('{"kind": "qlearn", "world": "square", "seed": 1}\n')
    code, stderr = figure(name, results, "-o", tmp_path / "f.png")
    assert code == 2, stderr
    assert len(stderr.splitlines()) == 1
    assert stderr.startswith(f"tvl: error: {results}: ")
    assert name in stderr
    assert not (tmp_path / "f.png").exists()


@pytest.mark.parametrize(
    ("line", "problem"),
    [
        ('{"kind": "tvl", "world": 5}', "'world' is 5, expected text"),
        ('{"kind": "tvl", "seed": "x"}', "'seed' is 'x', expected a number"),
        (
            '{"kind": "tvl", "contacts_per_min": true}',
            "'contacts_per_min' is True, expected a number",
        ),
        ('{"kind": "tvl", "online": "yes"}', "'online' is 'yes', expected true or false"),
    ],
)
def test_figure_names_the_line_with_a_value_of_the_wrong_type(tmp_path, line, problem):
    results = tmp_path / "results.jsonl"
    results.write_text('{"kind": "learn"}\n' + line + "\n")
    code, stderr = figure("fig27", results, "-o", tmp_path / "f.png")
    assert code == 2, stderr
    assert stderr == f"tvl: error: {results}:2: {problem}\n"
