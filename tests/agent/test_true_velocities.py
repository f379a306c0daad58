"""The oracle velocities (agent.true_velocities): the decision rule fed the true velocity of
every view's trajectories, a reference that reads the map."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from tvl_cli.agent.true_velocities import TrueVelocities, behave_with_true_velocities
from tvl_cli.core.method import DEFAULT
from tvl_cli.sim.worldmap import load_world

ROOT = Path(__file__).resolve().parents[2]
SQUARE = load_world(ROOT / "worlds" / "square.txt")
ROBOT = DEFAULT.robot()


def test_each_view_is_the_true_velocity_of_facing_that_sonar() -> None:
    pose = [SQUARE.start[0], SQUARE.start[1], 0.0]
    velocities, experience = TrueVelocities(SQUARE, ROBOT, DEFAULT, lambda: tuple(pose)).perceive(
        np.full(16, 4.0)
    )
    assert velocities.shape == experience.shape == (16, 7)
    # Turned a quarter turn, view 4 becomes view 0.
    pose[2] = math.pi / 2
    turned, _ = TrueVelocities(SQUARE, ROBOT, DEFAULT, lambda: tuple(pose)).perceive(
        np.full(16, 4.0)
    )
    np.testing.assert_allclose(turned[0], velocities[4], atol=1e-9)
    assert (velocities <= np.array(ROBOT.v_max_mps) + 1e-12).all()


@pytest.mark.slow  # over a second
def test_fed_the_truth_the_choice_avoids_without_a_contact() -> None:
    metrics = behave_with_true_velocities(
        SQUARE, ROBOT, "avoid", minutes=0.5, seed=1, method=DEFAULT
    )
    assert metrics.contacts == 0 and metrics.mean_speed_mps > 0.3
