"""The experiments' numbers, without drawing anything."""

from __future__ import annotations

import subprocess
import sys

from tvl_cli.analysis.ablation_table import ablation_rows
from tvl_cli.analysis.goal_series import goal_methods
from tvl_cli.analysis.learning_time_table import learning_time_rows
from tvl_cli.analysis.time_to_competence import is_competent, time_to_competence


def run_row(**overrides: object) -> dict[str, object]:
    """One avoid run's JSON line: 5 simulated minutes, no contact, 0.4 m/s."""
    row: dict[str, object] = {
        "kind": "tvl",
        "world": "square",
        "seed": 1,
        "config": "single",
        "behaviour": "avoid",
        "method": "default",
        "reflexes": "all",
        "sim_s": 300.0,
        "distance_m": 120.0,
        "mean_speed_mps": 0.4,
        "mean_drive_speed_mps": 0.45,
        "collisions": 0,
        "near_misses": 0,
        "contacts": 0,
        "contacts_per_min": 0.0,
        "collisions_per_min": 0.0,
        "backoffs": 0,
        "spins": 0,
        "trapped": 0,
        "mean_clearance_m": 0.4,
        "mean_wall_clearance_m": None,
        "goal_reached": False,
        "time_to_goal_s": None,
    }
    row.update(overrides)
    return row


def test_near_misses_alone_make_a_run_incompetent():
    bumpless = run_row(near_misses=5, contacts=5, contacts_per_min=1.0)
    assert is_competent(run_row())
    assert not is_competent(bumpless)


def test_time_to_competence_is_the_first_passing_snapshot():
    snapshots = [
        run_row(minute=1.0, near_misses=3, contacts=3, contacts_per_min=0.6),
        run_row(minute=2.0),
        run_row(minute=3.0),
    ]
    assert time_to_competence(snapshots) == 2.0


def test_an_ablation_row_splits_contacts_into_collisions_and_near_misses():
    rows = [
        run_row(
            seed=1,
            reflexes="none",
            collisions=1,
            near_misses=4,
            contacts=5,
            contacts_per_min=1.0,
            backoffs=0,
        ),
        run_row(
            seed=2,
            reflexes="none",
            collisions=0,
            near_misses=2,
            contacts=2,
            contacts_per_min=0.4,
            backoffs=0,
        ),
        run_row(seed=1, reflexes="all", backoffs=10),
    ]
    table = {row[2]: row for row in ablation_rows(rows, "avoid")}
    assert list(table) == ["none", "all"]  # settings in the ablation's order, absent ones left out
    world, config, _, contacts, split, *_, backoffs, competent = table["none"]
    assert backoffs == "0.0"
    assert (world, config) == ("square", "single")
    # The mean over the seeds, ± its 95 % interval: t(0.975, 1) · 0.42 / √2.
    assert contacts == "0.70 ± 3.81"
    assert split == "0.10 + 0.60"  # the mean of each run's rate: (0.2 + 0) / 2, (0.8 + 0.4) / 2
    assert competent == "0/2"
    assert table["all"][-2] == "2.0"  # 10 back-offs in 5 minutes
    assert table["all"][-1] == "1/1"


def test_learning_time_rows_give_speed_and_contacts_per_minute_and_the_dwa_last():
    snapshots = [
        run_row(minute=5.0, seed=1, mean_speed_mps=0.2, contacts_per_min=1.0),
        run_row(minute=5.0, seed=2, mean_speed_mps=0.4, contacts_per_min=3.0),
        run_row(minute=10.0, seed=1, behaviour="wall", mean_speed_mps=0.3),
    ]
    dwa = [run_row(kind="dwa", mean_speed_mps=0.5, contacts_per_min=0.2)]
    series = [("single", "avoid", "default"), ("single", "wall", "default")]
    header, body = learning_time_rows(snapshots, series, dwa)
    assert header == [
        "minute",
        "single avoid, ours: m/s, contacts/min",
        "single wall, ours: m/s, contacts/min",
    ]
    # Two seeds: each mean ± t(0.975, 1) · s / √2; one seed: the mean alone.
    assert body[0] == ["5", "0.30 ± 1.27, 2.00 ± 12.71", "–, –"]
    assert body[1] == ["10", "–, –", "0.30, 0.00"]
    assert body[2] == ["DWA (avoid)", "0.50, 0.20", "–"]


def test_the_numbers_need_no_drawing_library():
    modules = (
        "result_rows", "aggregation", "time_to_competence", "result_text", "figure_needs",
        "method_table", "wall_threshold", "goal_series", "learning_time_table",
        "ablation_table", "online_table",
    )  # fmt: skip
    imports = ", ".join(f"tvl_cli.analysis.{name}" for name in modules)
    code = f"import sys, {imports}; print('matplotlib' in sys.modules)"
    loaded = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert loaded.stdout.strip() == "False", loaded.stderr


def test_goal_runs_read_through_another_memory_are_a_series_of_their_own():
    goal = {"behaviour": "goal", "goal": "1,1"}
    own = [run_row(**goal, seed=seed, goal_reached=False) for seed in (1, 2)]
    unremembering = [
        run_row(**goal, seed=seed, goal_reached=True, run_memory="none") for seed in (1, 2)
    ]
    paper = [run_row(**goal, method="paper", reflexes="none", goal_reached=True)]
    series = dict(goal_methods([*own, *unremembering, *paper]))
    assert list(series) == [
        "TVL single, ours",
        "TVL single, ours, run with memory none",
        "TVL single, paper's method",
    ]
    assert series["TVL single, ours"] == own
    assert series["TVL single, ours, run with memory none"] == unremembering
