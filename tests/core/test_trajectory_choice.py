"""Choosing among fast trajectories (paper §2.1–2.2, §4.5), on hand-made perceptions."""

from __future__ import annotations

from typing import Any

import numpy as np

from tvl_cli.agent.reflexes import keep_out_ways
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.trajectory_choice import Choice, Context, choose, fast_set, trajectory_headings

ROBOT = RobotConfig()
V_MAX = np.array(ROBOT.v_max_mps)  # (7,) T3L .. T3R
CURVATURES = np.array([t.curvature_per_m for t in ROBOT.trajectories])
HEADINGS = trajectory_headings(CURVATURES, ROBOT.sonar.count)
STARTS = trajectory_headings(CURVATURES, ROBOT.sonar.count, 0.15)  # T3 sets off 17 degrees
T3L, T2L, T1L, T0, T1R, T2R, T3R = range(7)
FAR = np.full(16, 4.0)  # (16,) metres: nothing in sight


def slow_everywhere() -> np.ndarray:
    """(16, 7) perceived m/s, every trajectory in every direction well under the threshold."""
    return np.tile(0.3 * V_MAX, (16, 1))


def perceiving(fast: dict[int, list[int]]) -> np.ndarray:
    """(16, 7) perceived m/s with exactly the given trajectories fast, by rotation."""
    velocities = slow_everywhere()
    for rotation, trajectories in fast.items():
        velocities[rotation % 16, trajectories] = V_MAX[trajectories]
    return velocities


def pick(
    velocities: np.ndarray,
    behaviour: str,
    ring_m: np.ndarray = FAR,
    blocked_bearings_rad: tuple[float, ...] = (),
    **context: Any,
) -> Choice | None:
    fast = fast_set(velocities, V_MAX, 0.85)
    if blocked_bearings_rad:
        fast &= ~keep_out_ways(list(blocked_bearings_rad))(STARTS)
    return choose(velocities, fast, V_MAX, HEADINGS, behaviour, Context(ring_m, **context))


def test_avoid_goes_straight_when_straight_is_fast() -> None:
    choice = pick(perceiving({0: list(range(7))}), "avoid")
    assert choice == Choice(0, T0, V_MAX[T0])


def test_the_speed_is_the_perceived_velocity() -> None:
    velocities = perceiving({0: [T0]})
    velocities[0, T0] = 0.9 * V_MAX[T0]
    choice = pick(velocities, "avoid")
    assert choice is not None and choice.speed_mps == 0.9 * V_MAX[T0]


def test_avoid_tie_keeps_the_side_of_the_last_turn() -> None:
    velocities = perceiving({0: [T1L, T1R, T3L, T3R]})
    assert pick(velocities, "avoid", tie_side=1) == Choice(0, T1L, V_MAX[T1L])
    assert pick(velocities, "avoid", tie_side=-1) == Choice(0, T1R, V_MAX[T1R])


def ring_with_object_at(sonar: int) -> np.ndarray:
    """(16,) metres: one object 0.6 m from `sonar`, nothing else in sight."""
    ring = FAR.copy()
    ring[sonar] = 0.6
    return ring


def test_wall_left_takes_the_fast_trajectory_nearest_the_wall_alongside() -> None:
    velocities = perceiving({0: [T3L, T2L, T1L, T0]})
    choice = pick(velocities, "wall-left", wall_side=1, ring_m=ring_with_object_at(4))
    assert choice == Choice(0, T3L, V_MAX[T3L])


def test_wall_following_never_takes_a_trajectory_that_turns_past_the_wall() -> None:
    # The object 45 degrees off: T3L would turn past it (57 degrees after 0.5 m); T2L does not.
    velocities = perceiving({0: list(range(7))})
    left = pick(velocities, "wall-left", wall_side=1, ring_m=ring_with_object_at(2))
    right = pick(velocities, "wall-right", wall_side=-1, ring_m=ring_with_object_at(14))
    assert left == Choice(0, T2L, V_MAX[T2L])
    assert right == Choice(0, T2R, V_MAX[T2R])


def test_wall_following_goes_straight_on_until_a_wall_is_seen() -> None:
    velocities = perceiving({0: [T1L, T0, T1R]})
    assert pick(velocities, "wall-left", wall_side=0) == Choice(0, T0, V_MAX[T0])


def test_no_fast_trajectory_ahead_takes_the_nearest_rotated_one() -> None:
    choice = pick(perceiving({3: [T0], -2: [T0], 6: list(range(7))}), "avoid")
    assert choice == Choice(-2, T0, V_MAX[T0])


def test_a_bump_makes_the_way_it_met_the_obstacle_not_fast() -> None:
    # Straight ahead blocked: every trajectory facing as now sets off within 45 degrees of it.
    velocities = perceiving({0: list(range(7)), 3: [T0]})
    assert pick(velocities, "avoid") == Choice(0, T0, V_MAX[T0])
    assert pick(velocities, "avoid", blocked_bearings_rad=(0.0,)) == Choice(3, T0, V_MAX[T0])


def test_the_blocked_way_is_blocked_in_every_rotated_view() -> None:
    # Facing sonar 2 (45 degrees left), T2R sets off 36 degrees left: inside the blocked way.
    velocities = perceiving({2: [T2R], -4: [T0]})
    assert pick(velocities, "avoid") == Choice(2, T2R, V_MAX[T2R])
    assert pick(velocities, "avoid", blocked_bearings_rad=(0.0,)) == Choice(-4, T0, V_MAX[T0])


def test_every_blocked_way_counts() -> None:
    velocities = perceiving({0: [T0], 4: [T0], -4: [T0]})
    blocked = (0.0, np.pi / 2)  # straight ahead and to the left
    assert pick(velocities, "avoid", blocked_bearings_rad=blocked) == Choice(-4, T0, V_MAX[T0])


def test_equally_good_views_either_side_go_to_the_tie_side() -> None:
    velocities = perceiving({4: [T0], -4: [T0]})
    assert pick(velocities, "avoid", tie_side=1) == Choice(4, T0, V_MAX[T0])
    assert pick(velocities, "avoid", tie_side=-1) == Choice(-4, T0, V_MAX[T0])
    assert pick(velocities, "goal", tie_side=-1, goal_bearing_rad=0.0) == Choice(-4, T0, V_MAX[T0])


def test_a_tie_goes_to_the_trajectory_heading_to_the_tie_side() -> None:
    # Facing sonar 4 (90 degrees left), T3R ends 33 degrees left and T3L 147: T3R is the
    # nearest straight on however the robot last turned; facing sonar -4 the mirror of it.
    velocities = perceiving({4: list(range(7)), -4: list(range(7))})
    assert pick(velocities, "avoid", tie_side=-1) == Choice(-4, T3L, V_MAX[T3L])
    assert pick(velocities, "avoid", tie_side=1) == Choice(4, T3R, V_MAX[T3R])


def test_nothing_fast_in_any_direction_is_trapped() -> None:
    assert pick(slow_everywhere(), "avoid") is None
    velocities = perceiving({0: list(range(7))})
    assert pick(velocities, "avoid", blocked_bearings_rad=(0.0,)) is None


def test_wall_left_and_wall_right_are_mirror_images_when_readings_tie() -> None:
    # Nothing in range on either side: every sonar reads its maximum.
    velocities = perceiving({0: list(range(7))})
    left = pick(velocities, "wall-left", wall_side=1)
    right = pick(velocities, "wall-right", wall_side=-1)
    assert left is not None and right is not None
    assert (left.rotation, right.rotation) == (0, 0)
    assert right.trajectory == 6 - left.trajectory


def test_goal_takes_the_fast_trajectory_heading_nearest_the_goal() -> None:
    velocities = perceiving({0: list(range(7))})
    # After the half-metre look-ahead T2L (radius 1 m) heads 0.5 rad left, T1R 0.25 rad right.
    assert pick(velocities, "goal", goal_bearing_rad=0.45) == Choice(0, T2L, V_MAX[T2L])
    assert pick(velocities, "goal", goal_bearing_rad=-0.3) == Choice(0, T1R, V_MAX[T1R])


def test_goal_behind_turns_perception_towards_it_when_nothing_ahead_is_fast() -> None:
    choice = pick(perceiving({8: [T0], 2: [T0]}), "goal", goal_bearing_rad=3.0)
    assert choice is not None and choice.rotation == 2  # the nearer rotation wins first
    choice = pick(perceiving({-2: [T0], 2: [T0]}), "goal", goal_bearing_rad=1.0)
    assert choice == Choice(2, T0, V_MAX[T0])


def test_with_no_tie_side_a_tie_takes_the_first_in_trajectory_order() -> None:
    # The paper is silent on ties: T1L and T1R equally near straight on, the left one wins,
    # and of two equally good views, the one to the left.
    velocities = perceiving({0: [T1L, T1R]})
    assert pick(velocities, "avoid", tie_side=0) == Choice(0, T1L, V_MAX[T1L])
    assert pick(perceiving({4: [T0], -4: [T0]}), "avoid", tie_side=0) == Choice(4, T0, V_MAX[T0])
