"""Collision points heard (core.heard): every point labels all seven trajectories from the
echoes heard around it, placed by odometry, never by the true pose or the map."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tvl_cli.core.arcs import collision_clearance_m, first_contacts_m
from tvl_cli.core.episode import Episode
from tvl_cli.core.heard import HeardLabeller, heard_episodes
from tvl_cli.core.labels import DEFAULT_DECEL_MPS2, DEFAULT_MARGIN_M, velocity_labels
from tvl_cli.core.ring import ring_to_mm
from tvl_cli.core.robot_config import RobotConfig

ROBOT = RobotConfig()
CURVATURES = np.array([t.curvature_per_m for t in ROBOT.trajectories])
T0 = 3
WALL_X = 2.0  # a long wall across the way, x = 2 m
STEP_S = ROBOT.control_period_s
# Echoes sought however far along: every distance exact, as the geometry below gives it.
NO_REACH = math.inf


def axis_ring(pose: np.ndarray) -> np.ndarray:
    """(16,) metres: what each transducer reads of the wall along its axis (the maximum where
    its axis does not meet the wall within range): echoes that lie on the wall itself."""
    ring = np.full(16, ROBOT.sonar.max_range_m)
    for k in range(16):
        facing = math.cos(pose[2] + k * 2 * math.pi / 16)
        if facing > 1e-9:
            reach = (WALL_X - pose[0] - ROBOT.radius_m * facing) / facing
            ring[k] = min(reach, ROBOT.sonar.max_range_m)
    return ring


def episode(index: int, odometry: np.ndarray, start_s: float, end_arc_m: float) -> Episode:
    """The robot driving T0 through `odometry` (n, 3), one reading a step, the true pose
    left unknown (NaN): no label may read it."""
    arc = np.hypot(*(odometry[:, :2] - odometry[0, :2]).T)
    return Episode(
        index=index,
        ring_mm=ring_to_mm(np.array([axis_ring(p) for p in odometry])),
        pose=np.full(odometry.shape, np.nan),
        odometry=odometry,
        arc_m=arc,
        trajectory=T0,
        rotation=0,
        collided=math.isfinite(end_arc_m),
        bumped=math.isfinite(end_arc_m),
        end_arc_m=end_arc_m,
        end_time_s=start_s + len(odometry) * STEP_S,
    )


def toward_and_away() -> tuple[Episode, Episode]:
    """Up the x axis 2 cm a step to 1.2 m from the start (the wall 2 m ahead: it would bump
    at 1.8 m), then, turned about, 1 cm a step back: the window of each point of the first
    is heard whole."""
    toward = np.stack([np.arange(60) * 0.02, np.zeros(60), np.zeros(60)], axis=1)
    away = np.stack([1.2 - np.arange(120) * 0.01, np.zeros(120), np.full(120, math.pi)], axis=1)
    first = episode(0, toward, 0.0, WALL_X - ROBOT.radius_m)
    return first, episode(1, away, first.end_time_s, math.inf)


REACH_M = ROBOT.radius_m + collision_clearance_m(ROBOT)


def wall_distances(odometry: np.ndarray) -> np.ndarray:
    """(n, 7) metres along each trajectory from each pose to where the body comes within the
    collision clearance of the wall: the arc clearance, from the wall itself as points a
    millimetre apart."""
    wall = np.stack([np.full(20_001, WALL_X), np.linspace(-10.0, 10.0, 20_001)], axis=1)
    return np.array([first_contacts_m(tuple(p), CURVATURES, wall, REACH_M) for p in odometry])


@pytest.mark.slow
def test_the_heard_labels_of_all_seven_arcs_are_the_arc_clearance_to_a_known_wall() -> None:
    first, second = toward_and_away()
    labelled = heard_episodes([first, second], ROBOT, ended=True, reach_m=NO_REACH, window_s=10.0)
    heard = labelled[0].distances_m
    truth = wall_distances(first.odometry)
    reaching = np.isfinite(truth)
    # An arc that never reaches the wall (T3 turns back within 1 m; T2 from the first poses)
    # is heard free, and one that does is heard to meet it.
    np.testing.assert_array_equal(np.isfinite(heard), reaching)
    # Within the ring's resolution: its axes are 22.5° apart, so the echoes on the wall
    # leave gaps the body's edge may cross, and millimetre readings met at a grazing angle
    # move the contact along the arc. At most 0.03 m/s in any label.
    v_max = np.array(ROBOT.v_max_mps)
    truth[:, T0] = heard[:, T0]  # the driven one is the episode's own, below
    labels = (
        velocity_labels(d, v_max, DEFAULT_DECEL_MPS2, DEFAULT_MARGIN_M) for d in (heard, truth)
    )
    assert np.abs(np.subtract(*labels)).max() <= 0.03
    # The driven trajectory keeps its own collision point: the bump 1.8 m along it.
    np.testing.assert_allclose(heard[:, T0], WALL_X - ROBOT.radius_m - first.arc_m)


def test_the_labels_never_read_the_true_pose() -> None:
    first, second = toward_and_away()
    with_nan = heard_episodes([first, second], ROBOT, ended=True, reach_m=NO_REACH)[0].distances_m
    true_pose = np.array(first.odometry)  # what a true pose would hold here, given anew
    again = Episode(
        **{**{f: getattr(first, f) for f in first.__dataclass_fields__}, "pose": true_pose}
    )
    given = heard_episodes([again, second], ROBOT, ended=True, reach_m=NO_REACH)[0].distances_m
    np.testing.assert_array_equal(with_nan, given)
    assert not np.isnan(with_nan[:, T0]).any()


def test_an_episode_waits_until_its_window_after_is_heard() -> None:
    first, second = toward_and_away()
    labeller = HeardLabeller(ROBOT, NO_REACH, window_s=10.0)
    assert labeller.add(first) == []  # nothing heard after its last point yet
    (ready,) = labeller.add(second)  # 12 s after it: its window whole
    assert ready.episode is first and not np.isnan(ready.distances_m).any()
    (last,) = labeller.finish()
    # The session ended 10 s into the second's last 12 s: its first 2 s of points were heard
    # whole after; the rest label their driven trajectory alone, from its own (none: free)
    # collision point.
    assert last.episode is second
    heard_whole = round(2.0 / STEP_S)
    others = np.delete(last.distances_m, T0, axis=1)
    assert not np.isnan(others[:heard_whole]).any() and np.isnan(others[heard_whole:]).all()
    assert np.isinf(last.distances_m[:, T0]).all()


def test_a_stretch_driven_while_behaving_keeps_the_nearer_of_its_own_point_and_the_heard_one() -> (
    None
):
    first, second = toward_and_away()
    # The same drive toward the wall as a behaving stretch that ended by choice, its own
    # collision point estimated far beyond the wall (10 m along) from a few seconds of echoes.
    hopeful = Episode(
        **{**{f: getattr(first, f) for f in first.__dataclass_fields__}, "end_arc_m": 10.0}
    )
    explored, behaved = (
        heard_episodes([e, second], ROBOT, ended=True, reach_m=NO_REACH, behaving=b)[0]
        for e, b in ((first, False), (hopeful, True))
    )
    heard_wall = wall_distances(first.odometry)[:, T0]
    # Exploring, the driven trajectory keeps the point it met; behaving, the estimate gives
    # way to the wall heard nearer, within the ring's resolution (as above).
    np.testing.assert_allclose(explored.distances_m[:, T0], WALL_X - ROBOT.radius_m - first.arc_m)
    np.testing.assert_allclose(behaved.distances_m[:, T0], heard_wall, atol=0.05)
    assert (behaved.distances_m[:, T0] < 10.0 - first.arc_m).all()
    # Every other trajectory is labelled alike either way: from the echoes alone.
    others = [t for t in range(len(CURVATURES)) if t != T0]
    np.testing.assert_array_equal(explored.distances_m[:, others], behaved.distances_m[:, others])
    # An estimate nearer than anything heard stands.
    wary = Episode(
        **{**{f: getattr(first, f) for f in first.__dataclass_fields__}, "end_arc_m": 1.5}
    )
    (kept, _) = heard_episodes([wary, second], ROBOT, ended=True, reach_m=NO_REACH, behaving=True)
    np.testing.assert_allclose(kept.distances_m[:, T0], 1.5 - first.arc_m)


def test_a_snapshot_of_a_session_that_went_on_labels_only_what_was_heard() -> None:
    first, second = toward_and_away()
    # Cut short, the session had not ended: the second waits, unlabelled, as its learner's did.
    labelled = heard_episodes([first, second], ROBOT, ended=False, reach_m=NO_REACH)
    assert [h.episode for h in labelled] == [first]


@pytest.mark.parametrize("window_s", [1.0, 5.0])
def test_a_shorter_window_hears_less_of_the_wall(window_s: float) -> None:
    first, second = toward_and_away()
    heard, long = (
        heard_episodes([first, second], ROBOT, ended=True, reach_m=NO_REACH, window_s=w)[0]
        for w in (window_s, 10.0)
    )
    # Fewer echoes: the body meets one no sooner.
    both = np.isfinite(heard.distances_m) & np.isfinite(long.distances_m)
    assert (heard.distances_m[both] >= long.distances_m[both] - 1e-12).all()
