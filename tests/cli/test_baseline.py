"""`tvl baseline dwa` and `tvl baseline qlearn` on the command line, run in process."""

from __future__ import annotations

import subprocess
from collections.abc import Callable
from dataclasses import fields
from pathlib import Path

import pytest
from json_schemas import ENVELOPE, valid

from tvl_cli.core.metrics import RunMetrics

WORLDS = Path(__file__).resolve().parents[2] / "worlds"
SQUARE = WORLDS / "square.txt"
RUN_KEYS = {f.name for f in fields(RunMetrics)}
Tvl = Callable[..., subprocess.CompletedProcess[str]]


def test_dwa_json_prints_the_run_metrics_keys(invoke_tvl: Tvl) -> None:
    done = invoke_tvl("baseline", "dwa", SQUARE, "--minutes", "0.5", "--json")
    assert done.returncode == 0, done.stderr
    metrics = valid("baseline dwa", done.stdout)
    assert set(metrics) - ENVELOPE == RUN_KEYS
    assert metrics["inputs"]["minutes"] == 0.5 and metrics["inputs"]["sensor"] == "map"
    # By the map, the DWA takes only its reflexes of a method: none unless chosen.
    assert metrics["inputs"]["method"] == {"preset": None, "reflexes": []}
    assert abs(metrics["sim_s"] - 30.0) < 1e-9
    assert metrics["collisions"] == 0


def test_dwa_goal_seeking_draws_its_path(invoke_tvl: Tvl, tmp_path: Path) -> None:
    png = tmp_path / "path.png"
    done = invoke_tvl(
        "baseline", "dwa", WORLDS / "narrow.txt", "--behaviour", "goal", "--png", png, "--json"
    )
    assert done.returncode == 0, done.stderr
    printed = valid("baseline dwa", done.stdout)
    assert printed["goal_reached"] is True and printed["outputs"]["png"] == str(png)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.slow  # over a second: learns, runs or draws at length
def test_qlearn_json_adds_what_learning_cost(invoke_tvl: Tvl) -> None:
    done = invoke_tvl(
        "baseline", "qlearn", SQUARE, "--learn-minutes", "0.2", "--minutes", "0.1",
        "--competence-every", "0.1", "--json",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    report = valid("baseline qlearn", done.stdout)
    extra = {"learn_minutes", "learn_collisions", "time_to_competence_min", "competence_checks"}
    assert set(report) - ENVELOPE == RUN_KEYS | extra
    assert report["inputs"]["competence_every"] == 0.1
    assert report["inputs"]["method"] == {"preset": None, "reflexes": []}
    assert report["learn_minutes"] == 0.2
    assert [c["learn_minutes"] for c in report["competence_checks"]] == [0.1, 0.2]


def test_qlearn_without_competence_checks_prints_only_the_learning_keys(invoke_tvl: Tvl) -> None:
    done = invoke_tvl(
        "baseline", "qlearn", SQUARE, "--learn-minutes", "0.1", "--minutes", "0.1", "--json"
    )
    assert done.returncode == 0, done.stderr
    report = valid("baseline qlearn", done.stdout)
    assert set(report) - ENVELOPE == RUN_KEYS | {"learn_minutes", "learn_collisions"}


def test_qlearn_without_learning_runs_the_untrained_table(invoke_tvl: Tvl) -> None:
    done = invoke_tvl(
        "baseline", "qlearn", SQUARE, "--learn-minutes", "0", "--minutes", "0.1", "--json"
    )
    assert done.returncode == 0, done.stderr
    report = valid("baseline qlearn", done.stdout)
    assert (report["learn_minutes"], report["learn_collisions"], report["sim_s"]) == (0, 0, 6.0)


def test_bad_options_are_one_line_errors(invoke_tvl: Tvl) -> None:
    for args, message in (
        (("dwa", SQUARE, "--minutes", "-1"), "--minutes -1"),
        (("dwa", SQUARE, "--behaviour", "goal"), "world has no goal"),
        (("dwa", SQUARE, "--goal", "1,1"), "--goal is for --behaviour goal only"),
        (("qlearn", SQUARE, "--learn-minutes", "nan"), "--learn-minutes nan"),
        (("qlearn", SQUARE, "--competence-every", "0"), "--competence-every 0"),
        (("dwa", WORLDS / "missing.txt"), "no such world file"),
    ):
        done = invoke_tvl("baseline", *args)
        assert done.returncode == 2, args
        assert done.stderr.count("\n") == 1 and done.stderr.startswith("tvl: error: "), done.stderr
        assert message in done.stderr
