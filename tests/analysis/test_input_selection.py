"""Choosing FAM inputs from data: the informative sonar first, the budget, symmetry, the seed."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from doc_pages import page, section

from tvl_cli.analysis.input_selection import (
    DEFAULT_BUDGET_RULES,
    GROUP_SIZES,
    HELDOUT_FRACTION,
    MAX_TRAIN_EXEMPLARS,
    MIN_GAIN_MPS,
    SET_COUNTS,
    Design,
    design_inputs,
    least_budget_rules,
)
from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import MULTI, InputChoice
from tvl_cli.core.heard import HeardEpisode
from tvl_cli.core.ring import mm_to_ring, ring_to_mm
from tvl_cli.core.robot_config import RobotConfig, mirror_sonar, mirror_trajectory
from tvl_cli.core.training import TrainParams, driven_labels

ROBOT = RobotConfig()
NAMES = [t.name for t in ROBOT.trajectories]
STEP_M = 0.05  # arc between recorded points


def informative(trajectory: int) -> int:
    """The one sonar that reads the distance to the collision point: S3 (left of ahead) for
    a left trajectory, its mirror image S13 for a right one, and S0 straight ahead (a sonar
    that is its own mirror image, so that a mirrored ring tells as much)."""
    mirror = mirror_trajectory(trajectory, len(NAMES))
    return 3 if trajectory < mirror else 13 if trajectory > mirror else 0


def episode(index: int, trajectory: int, start_m: float, rng: np.random.Generator) -> Episode:
    """An episode whose only informative reading is the distance to its collision point."""
    arc = np.arange(0.0, start_m - 0.1, STEP_M)  # (n,) m
    end = float(start_m)
    ring = rng.uniform(0.15, 4.0, (len(arc), 16))  # (n, 16) m, noise everywhere else
    ring[:, informative(trajectory)] = end - arc
    return Episode(
        index=index,
        ring_mm=ring_to_mm(ring),
        pose=np.zeros((len(arc), 3)),
        odometry=np.zeros((len(arc), 3)),
        arc_m=arc,
        trajectory=trajectory,
        rotation=0,
        collided=True,
        bumped=True,
        end_arc_m=end,
        end_time_s=float(index),
    )


def synthetic(per_trajectory: int = 6, seed: int = 0) -> list[HeardEpisode]:
    """Episodes of every trajectory, each labelling the one it drove (the paper's rule)."""
    rng = np.random.default_rng(seed)
    return [
        driven_labels(episode(7 * k + j, j, float(rng.uniform(1.0, 3.5)), rng), len(NAMES))
        for k in range(per_trajectory)
        for j in range(7)
    ]


def heard_straight(count: int = 12, seed: int = 0) -> list[HeardEpisode]:
    """Episodes that all drove T0, each point labelling every trajectory (the heard rule),
    with the distance to each trajectory's collision point read by its informative sonar."""
    rng = np.random.default_rng(seed)
    found = []
    for index in range(count):
        driven = episode(index, NAMES.index("T0"), float(rng.uniform(1.0, 3.5)), rng)
        distances = np.empty((driven.exemplar_count, len(NAMES)))  # (n, T) m
        ring = mm_to_ring(driven.ring_mm)
        for sonar in (3, 13):  # the left and right trajectories' (S0 reads T0's already)
            ring[:, sonar] = rng.uniform(0.3, 3.5, driven.exemplar_count)
        for j in range(len(NAMES)):
            distances[:, j] = ring[:, informative(j)]
        found.append(HeardEpisode(replace(driven, ring_mm=ring_to_mm(ring)), distances))
    return found


@pytest.fixture(scope="module")
def designed():
    return design_inputs(synthetic(), ROBOT, TrainParams(), seed=1)


# The informative sonar of each chosen table: S3 left of ahead for the left ones, S0 for T0.
INFORMATIVE_FIRST = {"T3L": ("S3",), "T2L": ("S3",), "T1L": ("S3",), "T0": ("S0",)}


def first_choices(design: Design) -> dict[str, InputChoice]:
    """Each table's first choice, by table name."""
    first: dict[str, InputChoice] = {}
    for choice in design.config.design.choices:
        first.setdefault(choice.table, choice)
    return first


def test_the_sonar_the_labels_depend_on_is_chosen_first_for_every_table(designed) -> None:
    first = first_choices(designed)
    assert {t: c.inputs for t, c in first.items()} == INFORMATIVE_FIRST
    for choice in first.values():
        # Knowing the distance, a table perceives the label closely; without, far off.
        assert choice.heldout_error_after_mps < 0.03 < 0.05 < choice.heldout_error_before_mps


def test_heard_labels_feed_every_table_from_episodes_that_drove_another() -> None:
    """Every episode drove straight ahead, yet each table finds the sonar its own labels
    depend on: a point labels every trajectory, and each table learns from all of them."""
    first = first_choices(design_inputs(heard_straight(), ROBOT, TrainParams(), seed=1))
    assert {t: c.inputs for t, c in first.items()} == INFORMATIVE_FIRST
    for choice in first.values():
        assert choice.heldout_error_after_mps < 0.2 * choice.heldout_error_before_mps


def test_right_tables_mirror_left_ones_and_the_straight_one_mirrors_itself(designed) -> None:
    tables = {t.name: t for t in designed.config.tables}
    assert [t.name for t in designed.config.tables] == NAMES
    for left, right in (("T1L", "T1R"), ("T2L", "T2R"), ("T3L", "T3R")):
        mirrored = [
            (tuple(mirror_sonar(s) for s in i.sonars), i.partition) for i in tables[left].inputs
        ]
        assert [(i.sonars, i.partition) for i in tables[right].inputs] == mirrored
        assert tables[right].trajectories == (right,)
    straight = {(frozenset(i.sonars), i.partition) for i in tables["T0"].inputs}
    assert {(frozenset(mirror_sonar(s) for s in g), p) for g, p in straight} == straight


def test_each_choice_lowers_its_tables_error_from_where_the_last_left_it(designed) -> None:
    last: dict[str, float] = {}
    for choice in designed.config.design.choices:
        if choice.table in last:
            assert choice.heldout_error_before_mps == last[choice.table]
        assert choice.heldout_error_after_mps < choice.heldout_error_before_mps
        last[choice.table] = choice.heldout_error_after_mps


def test_the_chosen_tables_score_as_the_whole_fam_trained_as_tvl_train_does(designed) -> None:
    """The straight table's last error during the choice is the error of the whole FAM,
    trained on the same episodes: the choice measured what training will give."""
    t0 = [c for c in designed.config.design.choices if c.table == "T0"][-1]
    ours = designed.scores[0]
    assert ours.config == designed.config.name
    assert dict(ours.error_by_trajectory_mps)["T0"] == pytest.approx(
        t0.heldout_error_after_mps, rel=1e-9
    )
    names = [s.config for s in designed.scores]
    assert names == [designed.config.name, "single", "multi", "designed"]
    assert ours.error_mps < designed.scores[1].error_mps


@pytest.mark.slow
@pytest.mark.parametrize("budget", [30, 200])
def test_the_budget_is_respected(budget: int) -> None:
    config = design_inputs(synthetic(), ROBOT, TrainParams(), budget, seed=1).config
    assert config.rule_count <= budget
    assert config.design.budget_rules == budget


def test_the_least_budget_gives_each_table_one_input_of_the_fewest_sets() -> None:
    least = least_budget_rules(ROBOT)
    assert least == min(SET_COUNTS) * (1 + 2 * 3)  # T0, and three left tables with mirrors
    config = design_inputs(synthetic(), ROBOT, TrainParams(), least, seed=1).config
    assert [t.shape for t in config.tables] == [(min(SET_COUNTS),)] * 7
    assert config.rule_count == least


def test_the_default_budget_is_the_multi_fams_rule_count() -> None:
    assert MULTI.rule_count == DEFAULT_BUDGET_RULES


def test_a_budget_too_small_for_one_input_per_table_is_refused() -> None:
    with pytest.raises(BadInput, match="--budget 13: too small for one input per table"):
        design_inputs(synthetic(), ROBOT, TrainParams(), 13)


@pytest.mark.slow  # over a second
def test_the_same_seed_chooses_the_same_and_another_holds_out_other_episodes() -> None:
    episodes = synthetic(per_trajectory=4)
    first, again, other = (
        design_inputs(episodes, ROBOT, TrainParams(), 30, seed) for seed in (5, 5, 6)
    )
    assert first.config == again.config and first.scores == again.scores
    assert first.config.design.choices != other.config.design.choices


def test_a_trajectory_pair_with_one_episode_is_refused() -> None:
    episodes = [e for e in synthetic() if e.episode.trajectory not in (0, 6)]
    episodes.append(synthetic(per_trajectory=1)[0])  # one T3L episode, no T3R
    with pytest.raises(BadInput, match=r"1 episode\(s\) of T3L or T3R: at least 2"):
        design_inputs(episodes, ROBOT, TrainParams())


def test_the_docs_quote_the_choices_constants() -> None:
    design = section(page("guide/learning.md"), "Inputs chosen from data")
    assert f"lowers its table's error by {MIN_GAIN_MPS:g} m/s" in design
    assert HELDOUT_FRACTION == 0.25 and "a quarter held out" in design
    assert f"Past {MAX_TRAIN_EXEMPLARS:,} exemplars" in design
    assert f"the `multi` FAM's {DEFAULT_BUDGET_RULES:,}" in design
    assert f"per table needs {least_budget_rules(ROBOT)} rules" in design
    assert f"with {', '.join(map(str, SET_COUNTS[:-1]))} or {SET_COUNTS[-1]} fuzzy sets" in design
    assert GROUP_SIZES == (1, 2, 3) and "one sonar or the nearest reading" in design
    assert "of two or three adjacent ones" in design
