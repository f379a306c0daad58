"""The exploratory learning loop on real worlds: choices, episodes and their labels."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from tvl_cli.agent.explore import Learner, spin_commands
from tvl_cli.agent.explore_rules import least_experienced
from tvl_cli.core.episode import Episode
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.training import episode_labels
from tvl_cli.sim.worldmap import load_world, parse_world

ROBOT = RobotConfig()
LIVE_RING = replace(DEFAULT, memory=NO_MEMORY)  # our method, perceiving the live ring
SQUARE = Path(__file__).resolve().parents[2] / "worlds" / "square.txt"
# A 12 m hall: room for T3's full circle (1 m across) from its middle.
HALL = "version: 1\nname: hall\ncell: 0.5\n\n" + "\n".join(
    ["#" * 24] + ["#" + "." * 22 + "#"] * 10 + ["#" + "." * 10 + ">" + "." * 11 + "#"]
    + ["#" + "." * 22 + "#"] * 10 + ["#" * 24]
)  # fmt: skip


def _learner(world_text_or_path: str | Path, minutes: float, seed: int = 1) -> Learner:
    world = (
        load_world(world_text_or_path)
        if isinstance(world_text_or_path, Path)
        else parse_world(world_text_or_path, "hall")
    )
    fam = Fam(SINGLE, [t.name for t in ROBOT.trajectories])
    return Learner(world, ROBOT, fam, LearnParams(minutes=minutes), LIVE_RING, seed)


def _episodes(learner: Learner) -> list[Episode]:
    found: list[Episode] = []
    learner.run(found.append, lambda minute: None)
    return found


def test_least_experienced_picks_an_untried_pair_before_a_tried_one() -> None:
    experience = np.full((16, 7), 3.0)
    experience[5, 2] = 0.0
    rng = np.random.default_rng(0)
    assert all(least_experienced(experience, rng) == (5, 2) for _ in range(20))


def test_least_experienced_draws_ties_from_the_generator() -> None:
    experience = np.zeros((16, 7))
    picks = {least_experienced(experience, np.random.default_rng(seed)) for seed in range(30)}
    assert len(picks) > 10


def test_the_first_episodes_try_pairs_not_tried_before() -> None:
    learner = _learner(SQUARE, minutes=2)
    tried = [(e.rotation, e.trajectory) for e in _episodes(learner)[:4]]
    assert len(set(tried)) == len(tried)


@pytest.mark.slow
def test_labels_along_a_collision_episode_brake_to_the_collision_point() -> None:
    learner = _learner(SQUARE, minutes=3)
    episode = next(e for e in _episodes(learner) if e.collided and e.exemplar_count > 10)
    params = learner.train_params
    # no faster than the trajectory's ceiling, its top speed or above it (core.labels)
    trajectory = episode.trajectory
    top = params.ceilings(ROBOT)[trajectory] * ROBOT.trajectories[trajectory].v_max_mps
    distance = episode.end_arc_m - episode.arc_m
    expected = np.minimum(
        top, np.sqrt(2 * params.decel_mps2 * np.maximum(distance - params.margin_m, 0.0))
    )
    labels = episode_labels(episode, ROBOT, params)
    np.testing.assert_allclose(labels, expected, rtol=1e-12)
    assert labels[-1] < labels[0]  # slower as the collision point nears
    assert labels[-1] == 0.0  # the last point lies within the margin


def test_a_full_circle_labels_every_point_its_trajectorys_ceiling() -> None:
    learner = _learner(HALL, minutes=3)
    circles = [e for e in _episodes(learner) if not e.collided]
    assert circles, "in an empty hall some arcs close their circle"
    ceilings = learner.train_params.ceilings(ROBOT)  # the tight arcs' above the top speed
    for episode in circles:
        top = ceilings[episode.trajectory] * ROBOT.trajectories[episode.trajectory].v_max_mps
        assert (episode_labels(episode, ROBOT, learner.train_params) == top).all()
        radius = ROBOT.trajectories[episode.trajectory].radius_m
        if math.isfinite(radius):
            assert episode.end_arc_m >= 2 * math.pi * radius - 1e-9


def test_spinning_to_a_rotation_turns_the_shorter_way_exactly() -> None:
    for offset, turn in ((3, 3), (12, -4), (8, -8)):
        commands = spin_commands(offset, ROBOT)
        total = sum(c.angular_radps for c in commands) * ROBOT.control_period_s
        assert math.isclose(total, turn * 2 * math.pi / 16)
        assert all(abs(c.angular_radps) <= ROBOT.spin_rate_radps + 1e-12 for c in commands)


@pytest.mark.slow
def test_minute_statistics_add_up_to_the_summary() -> None:
    learner = _learner(SQUARE, minutes=3)
    minutes: list = []
    summary = learner.run(lambda e: None, minutes.append)
    assert [m.minute for m in minutes] == [0, 1, 2]
    assert sum(m.episodes for m in minutes) == summary.episodes
    assert sum(m.exemplars for m in minutes) == summary.exemplars
    assert all(m.delta_v >= 0 for m in minutes) and minutes[0].delta_v > 0
