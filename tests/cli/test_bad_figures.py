"""Results files `tvl figure` cannot draw honestly, on the command line, run in process: one line,
exit 2, no PNG. Runs are small synthetic JSON lines (a sweep's rows) with the keys each figure
reads."""

from __future__ import annotations

import json
from dataclasses import asdict
from pathlib import Path

import pytest
from test_bad_numbers import assert_one_line_refusal

from tvl_cli.core.metrics import RunMetrics

METRICS = asdict(
    RunMetrics(
        sim_s=12.0,
        distance_m=3.6,
        mean_speed_mps=0.3,
        mean_drive_speed_mps=0.32,
        collisions=0,
        near_misses=1,
        contacts=1,
        contacts_per_min=5.0,
        collisions_per_min=0.0,
        backoffs=1,
        spins=0,
        trapped=0,
        mean_clearance_m=0.4,
        mean_wall_clearance_m=0.5,
        goal_reached=False,
        time_to_goal_s=None,
    )
)
TVL_RUN = {
    "kind": "tvl",
    "world": "square",
    "seed": 1,
    "config": "single",
    "method": "default",
    "reflexes": "all",
    "run_minutes": 0.2,
}


def wall_run(threshold: object = 0.65, **changes: object) -> dict:
    """A fig21 run: wall following at a velocity threshold."""
    return {**TVL_RUN, "behaviour": "wall-left", "threshold": threshold, **METRICS, **changes}


def snapshot(**changes: object) -> dict:
    """An avoid run with the FAM learnt by minute 1 (fig19, fig24, fig27)."""
    avoid = {"behaviour": "avoid", "threshold": 0.85, "mean_wall_clearance_m": None}
    return {**TVL_RUN, "minute": 1, **METRICS, **avoid, **changes}


def learn_run(**changes: object) -> dict:
    minute = {"session": "1", "minute": 1, "collisions": 1.0, "delta_v": 0.05}
    return {"kind": "learn", "world": "square", "seed": 1, "minutes": [minute], **changes}


def ablation_run(**changes: object) -> dict:
    return wall_run(**{"threshold": 0.85, "reflexes": "none", **changes})


def goal_run(**changes: object) -> dict:
    goal = {"behaviour": "goal", "threshold": 0.85, "goal": "1.0,1.0"}
    return {**TVL_RUN, **METRICS, **goal, **changes}


def draw(invoke_tvl, tmp_path: Path, name: str, lines: list[dict] | list[str]):
    """`tvl figure NAME` of these runs (objects, or text lines as they are); the process, the
    results file and the PNG it was asked for."""
    results, png = tmp_path / "results.jsonl", tmp_path / "figure.png"
    text = [line if isinstance(line, str) else json.dumps(line) for line in lines]
    results.write_text("\n".join(text) + "\n")
    return invoke_tvl("figure", name, results, "-o", png), results, png


GOOD = {
    "fig19": [learn_run(), snapshot()],
    "fig21": [wall_run(0.65), wall_run(0.95)],
    "fig22": [goal_run()],
    "ablation": [ablation_run(), ablation_run(config="multi")],
}


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(GOOD))
def test_the_synthetic_runs_are_drawn(invoke_tvl, tmp_path, name):
    """The runs the refusals below spoil are ones the figure draws."""
    result, _, png = draw(invoke_tvl, tmp_path, name, GOOD[name])
    assert result.returncode == 0, result.stderr
    assert png.exists()


NESTED_LISTS = "[" * 200_000 + "]" * 200_000
NESTED_OBJECTS = '{"a": ' * 200_000 + "1" + "}" * 200_000
# name: (figure, its lines, the last one bad; what the one line of stderr says after FILE:LINE)
BAD_LINES = {
    "nested lists": ("fig21", [NESTED_LISTS], "nested too deeply"),
    "nested objects": ("fig21", [wall_run(), NESTED_OBJECTS], "nested too deeply"),
    "a 5001-digit seed": ("fig21", ['{"kind": "tvl", "seed": 1' + "0" * 5000 + "}"], "digits"),
    "minutes that are text": ("fig19", [snapshot(), learn_run(minutes="lots")], "'minutes'"),
    "minutes not objects": ("fig19", [snapshot(), learn_run(minutes=[1, 2])], "'minutes' item 1"),
    "a NaN speed": ("fig21", [wall_run(mean_speed_mps=float("nan"))], "'mean_speed_mps'"),
    "an infinite speed": ("fig21", [wall_run(mean_speed_mps=float("inf"))], "'mean_speed_mps'"),
    "a -Infinity contact rate": (
        "fig21",
        [wall_run(contacts_per_min=float("-inf"))],
        "'contacts_per_min'",
    ),
    "a NaN in a learning minute": (
        "fig19",
        [learn_run(minutes=[{"minute": 0.0, "collisions": 1.0, "delta_v": float("nan")}])],
        "'delta_v'",
    ),
    "a speed that is null": ("fig21", [wall_run(mean_speed_mps=None)], "'mean_speed_mps'"),
    "goal reached 'yes'": ("fig22", [goal_run(goal_reached="yes")], "'goal_reached'"),
    "a threshold of -3": ("fig21", [wall_run(-3)], "'threshold' is -3, outside (0, 1]"),
    "a threshold of 1e300": ("fig21", [wall_run(1e300)], "'threshold'"),
    "a threshold of 0": ("ablation", [ablation_run(threshold=0)], "'threshold'"),
}


@pytest.mark.parametrize("case", BAD_LINES)
def test_a_bad_line_is_named_and_nothing_is_drawn(invoke_tvl, tmp_path, case):
    name, lines, phrase = BAD_LINES[case]
    result, results, png = draw(invoke_tvl, tmp_path, name, lines)
    assert_one_line_refusal(result, f"{results}:{len(lines)}: ", phrase)
    assert not png.exists()


# name: (figure, its runs, what is missing)
NOTHING_TO_DRAW = {
    "fig21 of avoid runs": ("fig21", [snapshot(), snapshot(seed=2)], "no wall runs"),
    "fig21 without wall clearances": (
        "fig21",
        [wall_run(mean_wall_clearance_m=None)],
        "'mean_wall_clearance_m'",
    ),
    "fig19 with no learning minutes": ("fig19", [learn_run(minutes=[]), snapshot()], "'minutes'"),
    "the ablation of unknown reflexes": ("ablation", [ablation_run(reflexes="most")], "no runs"),
}


@pytest.mark.parametrize("case", NOTHING_TO_DRAW)
def test_results_with_nothing_to_draw_are_refused(invoke_tvl, tmp_path, case):
    name, runs, phrase = NOTHING_TO_DRAW[case]
    result, results, png = draw(invoke_tvl, tmp_path, name, runs)
    assert_one_line_refusal(result, f"{results}: ", phrase, name)
    assert not png.exists()
