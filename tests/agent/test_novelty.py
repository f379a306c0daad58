"""The exploration rules beyond least experience (`tvl learn --explore`): random and novelty."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from tvl_cli.agent.explore import ExplorePolicy, Learner
from tvl_cli.agent.explore_rules import Novelty, random_pair
from tvl_cli.agent.novelty import NOVELTY_BIN_M, NOVELTY_LOOKAHEAD_M, Places
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT, NOVELTY, Method
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.worldmap import load_world

ROBOT = RobotConfig()
LIVE_RING = replace(DEFAULT, memory=NO_MEMORY)  # our method, perceiving the live ring
SQUARE = Path(__file__).resolve().parents[2] / "worlds" / "square.txt"
OPEN_RING = np.full(16, ROBOT.sonar.max_range_m)  # (16,) metres: nothing echoes
T0 = ROBOT.trajectory_index("T0")


def _fam() -> Fam:
    return Fam(SINGLE, [t.name for t in ROBOT.trajectories])


def _choices(rule: str, seed: int) -> list[tuple[int, int, float]]:
    """Each episode's pair and end time over a minute of learning in the square."""
    method = replace(LIVE_RING, exploration=rule)
    learner = Learner(load_world(SQUARE), ROBOT, _fam(), LearnParams(minutes=1), method, seed)
    episodes: list = []
    learner.run(episodes.append, lambda minute: None)
    return [(e.rotation, e.trajectory, e.end_time_s) for e in episodes]


def test_random_pairs_are_drawn_from_the_generator_alone() -> None:
    def draws(seed: int) -> list[tuple[int, int]]:
        rng = np.random.default_rng(seed)
        return [random_pair((16, 7), rng) for _ in range(200)]

    assert draws(5) == draws(5)
    assert draws(5) != draws(6)
    assert {pair for pair in draws(5)} <= {(r, t) for r in range(16) for t in range(7)}
    assert len(set(draws(5))) > 80  # spread over the 112 pairs, not stuck on a few


@pytest.mark.slow  # over a second
@pytest.mark.parametrize("rule", ["novelty", "random"])
def test_learning_with_a_rule_repeats_for_a_seed(rule: str) -> None:
    first = _choices(rule, seed=3)
    assert len(first) >= 3
    assert _choices(rule, seed=3) == first
    assert _choices(rule, seed=4) != first


def _policy(rule: str, seed: int) -> ExplorePolicy:
    return ExplorePolicy(
        ROBOT,
        _fam(),
        LearnParams(),
        np.random.default_rng(seed),
        true_pose=lambda: (0.0, 0.0, 0.0),
        on_episode=lambda episode: None,
        method=replace(LIVE_RING, exploration=rule),
    )


def _reaches_north(rotation: int, trajectory: int) -> bool:
    """Whether the pair's arc, set off from the origin facing +x, reaches within the
    look-ahead the bins north of those the tests visit (y >= one bin), where nothing has been."""
    heading = 2 * math.pi * rotation / 16
    curvature = ROBOT.trajectories[trajectory].curvature_per_m
    along = np.linspace(0.0, NOVELTY_LOOKAHEAD_M, 41)  # (41,) metres
    if curvature == 0:
        y = along * math.sin(heading)
    else:
        y = (math.cos(heading) - np.cos(heading + curvature * along)) / curvature
    return bool(y.max() >= NOVELTY_BIN_M)


def _visit_the_south(places: Places) -> None:
    """The odometry has been everywhere within 3 m of the origin south of y = 0.5 m."""
    for x in np.arange(-3.0, 3.0, 0.1):
        for y in np.arange(-3.0, 0.3, 0.1):
            places.visit((float(x), float(y), 0.0))


def test_novelty_sets_off_towards_the_bins_never_visited() -> None:
    for seed in range(10):
        policy = _policy(NOVELTY, seed)
        assert isinstance(policy.rule, Novelty)
        _visit_the_south(policy.rule.places)
        rotation, trajectory = policy.choose(OPEN_RING, (0.0, 0.0, 0.0))
        assert _reaches_north(rotation, trajectory), (seed, rotation, trajectory)


def test_least_experience_in_the_same_place_goes_south_too() -> None:
    """The contrast: with nothing learnt every pair ties, wherever it leads."""
    picks = [
        _policy("least-experience", seed).choose(OPEN_RING, (0.0, 0.0, 0.0)) for seed in range(30)
    ]
    assert not all(_reaches_north(*pick) for pick in picks)


def test_a_pair_reaches_no_further_than_the_first_echo_in_its_way() -> None:
    places = Places(ROBOT, stop_m=0.16)
    _visit_the_south(places)
    origin = (0.0, 0.0, 0.0)
    assert places.leading_to_new(OPEN_RING, origin)[4, T0]  # straight north, nothing in the way
    ring = OPEN_RING.copy()
    ring[4] = 0.5  # something 0.5 m north of the body's edge
    new = places.leading_to_new(ring, origin)
    assert not new[4, T0]  # it hides the new ground beyond
    assert new[1, T0]  # 22.5 degrees left of east passes it by
    assert not new[12, T0]  # due south is all visited


def test_a_place_aimed_at_no_longer_pulls() -> None:
    places = Places(ROBOT, stop_m=0.16)
    _visit_the_south(places)
    assert places.leading_to_new(OPEN_RING, (0.0, 0.0, 0.0))[4, T0]
    places.aim(4, T0)
    assert not places.leading_to_new(OPEN_RING, (0.0, 0.0, 0.0))[4, T0]


def test_an_unknown_rule_is_refused() -> None:
    with pytest.raises(
        BadInput, match="--explore 'bogus': choose least-experience, novelty, random"
    ):
        Method(exploration="bogus")
