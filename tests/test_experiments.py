"""The experiment scripts (experiments/*.sh) at their --tiny size, and `tvl figure`."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from collections.abc import Callable
from dataclasses import asdict, fields
from pathlib import Path
from typing import NamedTuple

import pytest
from conftest import TVL
from json_schemas import valid

from tvl_cli.analysis.results import is_competent, time_to_competence
from tvl_cli.core.competence import COMPETENCE_RUN_MINUTES
from tvl_cli.core.metrics import RunMetrics

EXPERIMENTS = Path(__file__).resolve().parent.parent / "experiments"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
METRICS = {f.name for f in fields(RunMetrics)}
# The kinds of run each script records, and the parameters its TVL behaviour runs carry.
SCRIPTS = {
    "fig19_learning_curves": ({"learn", "tvl", "dwa", "qlearn"}, {"world", "seed", "minute"}),
    "fig21_threshold": ({"tvl"}, {"world", "seed", "behaviour", "threshold"}),
    "fig22_goal_seeking": ({"tvl", "dwa"}, {"world", "seed", "config", "goal", "goal_index"}),
    "fig24_single_vs_multi": ({"learn", "tvl", "dwa", "qlearn"}, {"world", "config", "minute"}),
    "fig27_lab": ({"learn", "tvl", "dwa"}, {"world", "seed", "config", "minute", "behaviour"}),
    "ablation": ({"tvl"}, {"world", "seed", "config", "learning", "behaviour", "reflexes"}),
    "online": ({"tvl"}, {"world", "seed", "start_minutes", "threshold", "online", "minutes"}),
    "exploration": ({"learn", "tvl"}, {"world", "seed", "explore", "learnt_minutes"}),
}
# `tvl` subcommands that do a run's work; a resumed script must call none of them.
WORK = {"learn", "train", "run", "replay", "baseline"}


class Finished(NamedTuple):
    out: Path  # the script's --out directory
    env: dict[str, str]  # the environment it ran in, `tvl` logging its calls
    calls: Path  # where each `tvl` call's subcommand was logged


def shim_environment(directory: Path) -> tuple[dict[str, str], Path]:
    """A PATH whose `tvl` logs each call's subcommand to calls.txt, then runs the real one."""
    shim, calls = directory / "bin", directory / "calls.txt"
    shim.mkdir()
    (shim / "tvl").write_text(f'#!/bin/sh\necho "$1" >>"{calls}"\nexec "{TVL}" "$@"\n')
    (shim / "tvl").chmod(0o755)
    env = {**os.environ, "PATH": f"{shim}{os.pathsep}{os.environ['PATH']}"}
    return env, calls


def run_script(
    name: str, out: Path, env: dict[str, str], *options: str
) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [str(EXPERIMENTS / f"{name}.sh"), "--tiny", "--out", str(out), "-j", "2", *options],
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


@pytest.fixture(scope="module")
def tiny(tmp_path_factory: pytest.TempPathFactory) -> Callable[[str], Finished]:
    """Each script run to the end at --tiny size once, shared by the tests of this module."""
    finished: dict[str, Finished] = {}

    def get(name: str) -> Finished:
        if name not in finished:
            directory = tmp_path_factory.mktemp(name)
            env, calls = shim_environment(directory)
            out = directory / "out"
            result = run_script(name, out, env)
            assert result.returncode == 0, result.stderr
            finished[name] = Finished(out, env, calls)
        return finished[name]

    return get


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(SCRIPTS))
def test_tiny_run_writes_one_json_line_per_run_with_its_parameters(tiny, name):
    out = tiny(name).out
    kinds, parameters = SCRIPTS[name]
    lines = (out / "results.jsonl").read_text().splitlines()
    rows = [json.loads(line) for line in lines]
    assert len(rows) == len(list((out / "runs").glob("*.json")))
    assert {row["kind"] for row in rows} == kinds
    for row in rows:
        assert {"kind", "world", "seed"} <= row.keys()
        if row["kind"] in ("tvl", "dwa", "qlearn"):
            assert row.keys() >= METRICS
        if row["kind"] == "tvl":
            assert row.keys() >= parameters
        if row["kind"] == "learn":
            assert {"minute", "delta_v", "collisions"} <= row["minutes"][0].keys()


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(SCRIPTS))
def test_tiny_run_draws_a_png_and_a_summary_table(tiny, name):
    out = tiny(name).out
    assert (out / f"{name}.png").read_bytes().startswith(PNG_MAGIC)
    table = (out / "summary.md").read_text()
    assert table.startswith("### ") and "| --- |" in table


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(SCRIPTS))
def test_running_a_finished_script_again_repeats_no_run(tiny, name):
    out, env, calls = tiny(name)
    runs_before = {p.name: p.stat().st_mtime_ns for p in (out / "runs").iterdir()}
    calls.write_text("")
    again = run_script(name, out, env)
    assert again.returncode == 0, again.stderr
    assert not set(calls.read_text().split()) & WORK
    assert {p.name: p.stat().st_mtime_ns for p in (out / "runs").iterdir()} == runs_before


@pytest.mark.slow
def test_a_run_missing_from_a_finished_script_is_the_only_one_redone(tiny, tmp_path):
    out = tmp_path / "out"
    shutil.copytree(tiny("fig21_threshold").out, out)
    env, calls = shim_environment(tmp_path)
    victim = sorted((out / "runs").glob("*.json"))[0]
    victim.unlink()
    assert run_script("fig21_threshold", out, env).returncode == 0
    assert calls.read_text().split().count("run") == 1
    assert victim.exists()


@pytest.mark.slow
def test_another_size_into_the_same_out_dir_is_refused(tmp_path):
    env, calls = shim_environment(tmp_path)
    out = tmp_path / "out"
    (out).mkdir()
    (out / "size").write_text("quick\n")
    result = run_script("fig27_lab", out, env)
    assert result.returncode == 2
    assert "--quick" in result.stderr
    assert not calls.exists()


@pytest.mark.slow
def test_an_unknown_option_is_refused_before_any_run(tmp_path):
    env, calls = shim_environment(tmp_path)
    result = run_script("fig19_learning_curves", tmp_path / "out", env, "--trials")
    assert result.returncode == 2
    assert "unknown option --trials" in result.stderr
    assert not calls.exists()


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


def test_scripts_judge_competence_with_runs_of_the_defined_length():
    text = (EXPERIMENTS / "lib.sh").read_text()
    assert f"COMPETENCE_RUN_MINUTES={COMPETENCE_RUN_MINUTES:g}\n" in text


def test_time_to_competence_is_the_first_competent_snapshot_minute():
    runs = [avoid_run(6, 0.0, 0.4), avoid_run(3, 0.1, 0.35), avoid_run(4, 1.0, 0.4)]
    assert time_to_competence(runs) == 3
    assert time_to_competence([avoid_run(5, 0.4, 0.5)]) is None


def test_figure_names_the_line_that_is_not_json(run_tvl, tmp_path):
    results = tmp_path / "results.jsonl"
    results.write_text('{"kind": "tvl"}\n{"kind": \n')
    result = run_tvl("figure", "fig21", results, "-o", tmp_path / "f.png")
    assert result.returncode == 2
    assert result.stderr.startswith(f"tvl: error: {results}:2:")
    assert not (tmp_path / "f.png").exists()


def test_figure_refuses_an_unknown_name(run_tvl, tmp_path):
    results = tmp_path / "results.jsonl"
    results.write_text('{"kind": "tvl"}\n')
    result = run_tvl("figure", "fig99", results, "-o", tmp_path / "f.png")
    assert result.returncode == 2
    assert "unknown figure 'fig99'" in result.stderr


@pytest.mark.parametrize("name", ["fig19", "fig21", "fig22", "fig24", "fig27", "ablation"])
def test_figure_refuses_results_without_the_runs_it_draws(run_tvl, tmp_path, name):
    results = tmp_path / "results.jsonl"
    results.write_text('{"kind": "tvl", "world": "square", "seed": 1}\n')
    result = run_tvl("figure", name, results, "-o", tmp_path / "f.png")
    assert result.returncode == 2, result.stderr
    assert len(result.stderr.splitlines()) == 1
    assert result.stderr.startswith(f"tvl: error: {results}: ")
    assert name in result.stderr
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
    ],
)
def test_figure_names_the_line_with_a_value_of_the_wrong_type(run_tvl, tmp_path, line, problem):
    results = tmp_path / "results.jsonl"
    results.write_text('{"kind": "learn"}\n' + line + "\n")
    result = run_tvl("figure", "fig27", results, "-o", tmp_path / "f.png")
    assert result.returncode == 2, result.stderr
    assert result.stderr == f"tvl: error: {results}:2: {problem}\n"


def test_figure_json_names_its_files_and_carries_the_table(tiny, run_tvl, tmp_path):
    results = tiny("fig21_threshold").out / "results.jsonl"
    png, table = tmp_path / "f.png", tmp_path / "f.md"
    result = run_tvl("figure", "fig21", results, "-o", png, "--table", table, "--json")
    assert result.returncode == 0, result.stderr
    printed = valid("figure", result.stdout)
    assert printed["inputs"]["figure"] == "fig21"
    assert printed["inputs"]["results"]["path"] == str(results)
    assert printed["outputs"] == {"picture": str(png), "table": str(table)}
    assert printed["summary_markdown"] == table.read_text()
    assert png.read_bytes().startswith(PNG_MAGIC)
