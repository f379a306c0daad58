"""The registries a method's choices select from, beside the paper's modules: exploration
rules, collision points and wall rules, each keyed as core.method names them."""

from __future__ import annotations

import numpy as np

from tvl_cli.agent.collision_points import NEAR_CLOSING_M, sonar_collision_points
from tvl_cli.agent.explore_rules import EXPLORATION_RULES, LeastExperience, Novelty, RandomPair
from tvl_cli.core import method
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.wall_rules import FIRST_SEEN, WALL_RULES, WALL_SEEN_M

ROBOT = RobotConfig()
OPEN = np.full(16, ROBOT.sonar.max_range_m)  # (16,) metres: nothing echoes


def test_every_exploration_rule_a_method_names_is_in_the_registry() -> None:
    assert tuple(EXPLORATION_RULES) == method.EXPLORATION_RULES
    made = {name: make(ROBOT, method.DEFAULT) for name, make in EXPLORATION_RULES.items()}
    assert isinstance(made[method.LEAST_EXPERIENCE], LeastExperience)
    assert isinstance(made[method.NOVELTY], Novelty)
    assert isinstance(made[method.RANDOM], RandomPair)


def test_the_papers_learner_places_collision_points_at_bumps_alone() -> None:
    assert sonar_collision_points(ROBOT, method.PAPER.near_m) is None


def test_a_sonar_ahead_that_closed_in_within_near_marks_a_collision_point() -> None:
    points = sonar_collision_points(ROBOT, method.DEFAULT.near_m)
    assert points is not None
    start, now = OPEN.copy(), OPEN.copy()
    now[0] = 0.155  # straight ahead, inside 0.16 m
    assert points.reached(now, start)
    # As near, but it was as near when the episode began: a wall run beside, not met.
    assert not points.reached(now, now + NEAR_CLOSING_M / 2)
    behind = OPEN.copy()
    behind[8] = 0.155  # straight behind
    assert not points.reached(behind, start)


def test_the_first_seen_rule_finds_a_wall_within_a_metre_and_keeps_its_side() -> None:
    rule = WALL_RULES[FIRST_SEEN]
    assert method.DEFAULT.wall_rule == method.PAPER.wall_rule == FIRST_SEEN
    left_far, left_near = OPEN.copy(), OPEN.copy()
    left_far[4], left_near[4] = WALL_SEEN_M + 0.1, WALL_SEEN_M - 0.1  # S4: the left side
    assert rule("wall-left", left_far, 0) == 0  # not yet: go on as when avoiding
    assert rule("wall-left", left_near, 0) == 1
    assert rule("wall-right", left_near, 0) == 0  # a wall on the other side is not its wall
    assert rule("wall", left_near, 0) == 1  # either side: the nearest object's
    assert rule("wall", OPEN, -1) == -1  # once found, kept whatever the ring reads
    assert rule("avoid", left_near, 0) == 0
