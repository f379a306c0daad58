"""The DWA driving the real simulator in the bundled worlds."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from tvl_cli.agent.policy import LazyRing, Observation
from tvl_cli.baselines import dwa
from tvl_cli.baselines.dwa import RING, DwaPolicy, MapSensing, run_dwa
from tvl_cli.core.drive_command import Command
from tvl_cli.core.memory import PATCHES, MemoryConfig
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import load_world

WORLDS = Path(__file__).resolve().parents[2] / "worlds"
SQUARE = load_world(WORLDS / "square.txt")  # walls' inner faces at x, y = 0.25 and 3.75
ROBOT = RobotConfig()
CRUISING = Command(0.6, 0.0)
PATCHES_MEMORY = MemoryConfig(PATCHES)


def observe(sim: Simulator) -> Observation:
    return Observation(sim.time_s, LazyRing(sim.read_sonar), sim.odometry, sim.bumped)


def first_choice(x: float, y: float, theta: float) -> Command:
    """The first command of a DWA cruising straight at top speed from a pose in the square."""
    sim = Simulator(SQUARE, ROBOT, np.random.default_rng(0))
    sim.place(x, y, theta)
    policy = DwaPolicy(MapSensing(sim), ROBOT)
    policy.last = CRUISING
    return policy.decide(observe(sim)).command


def test_a_wall_ahead_makes_it_slow_down_and_turn() -> None:
    # Facing the east wall with 0.4 m between the body's edge and the wall.
    near_wall = first_choice(3.75 - ROBOT.radius_m - 0.4, 2.0, 0.0)
    open_space = first_choice(1.0, 2.0, 0.0)  # 2.35 m of room ahead
    assert open_space == CRUISING
    assert near_wall.linear_mps < open_space.linear_mps
    assert near_wall.angular_radps != 0.0


@pytest.mark.slow  # over a second
def test_it_avoids_for_a_minute_in_the_square_without_a_collision() -> None:
    metrics = run_dwa(SQUARE, ROBOT, 1.0, seed=1)
    # It never touches; it does pass walls inside the sonars' blind zone (near misses).
    assert metrics.collisions == 0
    assert metrics.mean_speed_mps > 0.4
    assert metrics.sim_s == pytest.approx(60.0)


def test_it_reaches_a_goal_behind_an_obstacle() -> None:
    world = load_world(WORLDS / "obstacles.txt")
    metrics = run_dwa(world, ROBOT, 1.0, seed=1, goal_xy=world.goals[1])
    assert metrics.goal_reached and metrics.collisions == 0


@pytest.mark.slow  # over a second
def test_driven_by_the_ring_alone_it_avoids_the_square_by_what_it_hears() -> None:
    metrics = run_dwa(SQUARE, ROBOT, 1.0, seed=1, sensor=RING)
    assert metrics.collisions == 0
    assert metrics.mean_speed_mps > 0.2


@pytest.mark.slow
def test_driven_by_the_ring_it_meets_a_wall_it_cannot_hear_that_the_map_sees() -> None:
    # The lab's thin table edges and slanted approaches: the ring-driven DWA meets what a
    # specular ring misses, the map-driven one does not.
    lab = load_world(WORLDS / "lab.txt")
    by_map = run_dwa(lab, ROBOT, 2.0, seed=1)
    by_ring = run_dwa(lab, ROBOT, 2.0, seed=1, sensor=RING)
    assert by_map.collisions == 0
    assert by_ring.collisions > 0


@pytest.mark.slow  # over a second
def test_how_far_the_walk_along_the_arcs_looks_changes_no_run_through_the_memory(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # The ring DWA through the echo memory, among the lab's crowded patches: the run with
    # obstacles sought only as near as the free distances read, and the walk along each arc
    # vouching for 0.15 m at most, is the run with both looking a metre or more.
    lab = load_world(WORLDS / "lab.txt")

    def run() -> tuple[float, int, int, float]:
        metrics = run_dwa(lab, ROBOT, 0.5, seed=2, sensor=RING, memory=PATCHES_MEMORY)
        return (
            metrics.distance_m,
            metrics.collisions,
            metrics.near_misses,
            metrics.mean_clearance_m,
        )

    bounded = run()
    monkeypatch.setattr(dwa, "clearance_read_m", lambda s_m, p: math.inf)
    monkeypatch.setattr(dwa, "WALK_M", 1.0)
    unbounded = run()
    assert bounded == unbounded
    assert bounded[0] > 1.0  # it drove
