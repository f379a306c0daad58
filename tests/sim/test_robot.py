"""The simulated robot in real pymunk: arcs, spins, speed limits, walls, bumps and odometry."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from test_geometry import room, square_block

from tvl_cli.core.drive_command import STOP, Command
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.geometry import clearances_m
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap

ROBOT = RobotConfig()
T0 = ROBOT.trajectories[ROBOT.trajectory_index("T0")]
T2L = ROBOT.trajectories[ROBOT.trajectory_index("T2L")]
T3R = ROBOT.trajectories[ROBOT.trajectory_index("T3R")]
EMPTY = room(40, 40)
# A small room with a block in it: walls at every angle, convex and concave corners.
CLUTTERED = room(3, 2.5, walls=square_block(1.75, 1.0, 0.5), start=(0.8, 1.25, 0.0))


def simulator(world: WorldMap = EMPTY, robot: RobotConfig = ROBOT, seed: int = 0) -> Simulator:
    return Simulator(world, robot, np.random.default_rng(seed))


def test_starts_at_the_world_start_pose() -> None:
    sim = simulator(CLUTTERED)
    assert sim.pose == pytest.approx(CLUTTERED.start)
    assert sim.odometry == pytest.approx(CLUTTERED.start)
    assert sim.time_s == 0.0 and not sim.bumped


def test_one_full_circle_on_t2l_returns_to_the_start_pose() -> None:
    sim = simulator()
    sim.place(20.0, 20.0, 0.3)
    # 140 control periods at just under T2L's top speed make exactly one circle of 1 m radius.
    speed = 2 * math.pi * T2L.radius_m / (140 * ROBOT.control_period_s)
    for _ in range(140):
        sim.step(Command.follow(T2L, speed))
    x, y, theta = sim.pose
    assert math.hypot(x - 20.0, y - 20.0) < 0.02
    assert theta - 0.3 == pytest.approx(2 * math.pi)


def test_t2l_turns_left_on_a_circle_of_its_radius() -> None:
    sim = simulator()
    sim.place(20.0, 20.0, 0.0)  # heading +x: the circle's centre is 1 m to the left, at +y
    for _ in range(37):
        sim.step(Command.follow(T2L, 0.45))
        x, y, _ = sim.pose
        assert math.hypot(x - 20.0, y - 21.0) == pytest.approx(1.0, abs=1e-6)


def test_t0_goes_straight() -> None:
    sim = simulator()
    sim.place(10.0, 20.0, 0.0)
    for _ in range(50):
        sim.step(Command.follow(T0, T0.v_max_mps))
    assert sim.pose == pytest.approx((13.0, 20.0, 0.0), abs=1e-9)


def test_negative_speed_reverses_along_the_same_arc() -> None:
    sim = simulator()
    sim.place(20.0, 20.0, 1.0)
    for speed in (0.35, -0.35):
        for _ in range(20):
            sim.step(Command.follow(T3R, speed))
    assert sim.pose == pytest.approx((20.0, 20.0, 1.0), abs=1e-9)


@pytest.mark.parametrize("name", [t.name for t in ROBOT.trajectories])
def test_the_body_never_moves_faster_than_commanded(name: str) -> None:
    trajectory = ROBOT.trajectories[ROBOT.trajectory_index(name)]
    sim = simulator()
    sim.place(20.0, 20.0, 0.0)
    for _ in range(30):
        before = sim.pose
        sim.step(Command.follow(trajectory, trajectory.v_max_mps))
        moved = math.dist(before[:2], sim.pose[:2])
        assert moved <= trajectory.v_max_mps * ROBOT.control_period_s + 1e-12
        turned = abs(sim.pose[2] - before[2])
        assert turned == pytest.approx(abs(trajectory.curvature_per_m) * moved, rel=1e-3)


def test_spin_turns_in_place_at_most_at_the_spin_rate() -> None:
    sim = simulator()
    sim.place(20.0, 20.0, 0.0)
    sim.step(Command.spin(5.0))
    assert sim.pose == pytest.approx((20.0, 20.0, ROBOT.spin_rate_radps * 0.1), abs=1e-12)
    sim.step(Command.spin(-0.5))
    assert sim.pose[2] == pytest.approx((ROBOT.spin_rate_radps - 0.5) * 0.1)


def test_stop_holds_the_body_still() -> None:
    sim = simulator()
    sim.place(20.0, 20.0, 0.5)
    sim.step(Command.follow(T0, 0.6))
    stopped_at = sim.pose
    sim.step(STOP)
    assert sim.pose == stopped_at


def test_time_advances_one_control_period_a_step() -> None:
    sim = simulator()
    for _ in range(25):
        sim.step(STOP)
    assert sim.time_s == pytest.approx(2.5)


def test_driving_into_a_wall_sets_bumped() -> None:
    sim = simulator(CLUTTERED)
    sim.place(0.8, 1.25, math.pi)  # 0.6 m from the left wall's line, facing it
    bumps = []
    for _ in range(20):
        sim.step(Command.follow(T0, 0.6))
        bumps.append(sim.bumped)
    assert bumps[:9] == [False] * 9  # 0.4 m to go at 6 cm a step
    assert all(bumps[11:])


def test_bumped_clears_after_backing_off() -> None:
    sim = simulator(CLUTTERED)
    sim.place(0.8, 1.25, math.pi)
    for _ in range(15):
        sim.step(Command.follow(T0, 0.6))
    sim.step(Command.follow(T0, -0.3))
    assert not sim.bumped


def test_contact_stops_the_body_at_the_wall_line() -> None:
    sim = simulator(CLUTTERED)
    sim.place(0.8, 1.25, math.pi)
    for _ in range(30):
        sim.step(Command.follow(T0, 0.6))
    assert sim.pose[0] == pytest.approx(ROBOT.radius_m, abs=0.002)
    assert sim.clearance_m() == pytest.approx(0.0, abs=0.002)


def test_placing_against_a_wall_counts_as_bumped() -> None:
    sim = simulator(CLUTTERED)
    sim.place(0.19, 1.25, 0.0)
    assert sim.bumped


@pytest.mark.parametrize("heading_deg", range(0, 360, 15))
def test_the_body_never_passes_through_walls_at_any_angle(heading_deg: int) -> None:
    sim = simulator(CLUTTERED)
    sim.place(0.8, 1.25, math.radians(heading_deg))
    deepest = 0.0
    # Straight into a wall, then arcs that grind along walls and into corners, for a minute.
    for command in [Command.follow(T0, 0.6)] * 300 + [Command.follow(T3R, 0.6)] * 300:
        sim.step(command)
        x, y, _ = sim.pose
        assert 0.0 < x < 3.0 and 0.0 < y < 2.5
        assert not (1.75 <= x <= 2.25 and 1.0 <= y <= 1.5)
        centre_gap = clearances_m(sim.geometry, np.array([[x, y]]), 0.0)[0]
        deepest = max(deepest, ROBOT.radius_m - centre_gap)
    # At most one sub-step's travel overlaps before the contact pushes back.
    assert deepest < 0.6 * ROBOT.control_period_s / ROBOT.physics_substeps + 0.002


def test_the_body_stays_inside_a_ring_wall() -> None:
    world = room(6, 6, rings=((3, 3, 1.5),), outline=False, start=(3, 3, 0))
    sim = simulator(world)
    for _ in range(600):
        sim.step(Command.follow(T0, 0.6))
        assert math.dist(sim.pose[:2], (3, 3)) < 1.5 - ROBOT.radius_m + 0.016


def test_same_seed_gives_identical_sonar_and_odometry_bit_for_bit() -> None:
    runs = []
    for _ in range(2):
        sim = simulator(CLUTTERED, seed=11)
        readings, odometry = [], []
        for command in [Command.follow(T2L, 0.4)] * 40 + [Command.spin(0.8)] * 10:
            sim.step(command)
            readings.append(sim.read_sonar())
            odometry.append(sim.odometry)
        runs.append((np.array(readings), np.array(odometry)))
    assert runs[0][0].tobytes() == runs[1][0].tobytes()
    assert runs[0][1].tobytes() == runs[1][1].tobytes()


def test_another_seed_gives_different_noise() -> None:
    first, other = simulator(CLUTTERED, seed=1), simulator(CLUTTERED, seed=2)
    for sim in (first, other):
        sim.step(Command.follow(T0, 0.3))
    assert not np.array_equal(first.read_sonar(), other.read_sonar())
    assert first.odometry != other.odometry
    assert first.pose == other.pose  # the noise is in the sensors, not the world


def test_odometry_without_noise_matches_the_true_pose() -> None:
    robot = dataclasses.replace(ROBOT, odometry_noise_fraction=0.0)
    sim = simulator(robot=robot)
    sim.place(20.0, 20.0, 0.2)
    for command in [Command.follow(T3R, 0.35)] * 30 + [Command.spin(-1.0)] * 7:
        sim.step(command)
    assert sim.odometry == pytest.approx(sim.pose, abs=1e-9)


def test_odometry_drifts_a_little_from_the_true_pose() -> None:
    sim = simulator()
    sim.place(20.0, 20.0, 0.0)
    for _ in range(100):
        sim.step(Command.follow(T0, 0.5))
    error = math.dist(sim.odometry[:2], sim.pose[:2])
    assert 0.0 < error < 0.25  # after 5 m with 1 % wheel noise


def test_odometry_stands_still_while_a_wall_holds_the_body() -> None:
    sim = simulator(CLUTTERED)
    sim.place(0.8, 1.25, math.pi)
    for _ in range(60):
        sim.step(Command.follow(T0, 0.6))
    assert sim.odometry[0] == pytest.approx(ROBOT.radius_m, abs=0.03)


def test_place_moves_the_robot_and_restarts_odometry() -> None:
    sim = simulator()
    sim.step(Command.follow(T0, 0.5))
    sim.place(5.0, 6.0, -1.0)
    assert sim.pose == pytest.approx((5.0, 6.0, -1.0))
    assert sim.odometry == (5.0, 6.0, -1.0)


def test_clearance_is_measured_from_the_body_edge() -> None:
    sim = simulator(CLUTTERED)
    sim.place(0.8, 1.25, 0.0)
    assert sim.clearance_m() == pytest.approx(0.6)  # left wall 0.8 m from the centre


def test_sonar_reads_the_world_from_the_true_pose() -> None:
    robot = dataclasses.replace(ROBOT, sonar=dataclasses.replace(ROBOT.sonar, ideal=True))
    sim = simulator(CLUTTERED, robot=robot)
    sim.place(0.8, 1.25, math.pi)
    readings = sim.read_sonar()
    assert readings.shape == (16,) and readings.dtype == np.float64
    assert readings[0] == pytest.approx(0.6)  # the left wall, straight ahead
    assert readings[8] == pytest.approx(0.75)  # the block, straight behind
