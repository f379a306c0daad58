"""Many robots a step in real pymunk worlds: each robot of a batch reads, moves, bumps and
dead-reckons bit for bit as a lone Simulator with its generator and commands would."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tvl_cli.core.drive_command import Command
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.batch import RobotBatch
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap, load_world

WORLDS = Path(__file__).resolve().parents[2] / "worlds"
ROBOT = RobotConfig()
T0 = ROBOT.trajectories[ROBOT.trajectory_index("T0")]
# Every trajectory near its top speed, spins both ways and reversing: straight runs at full
# speed drive into walls, which the arcs then slide along and the corners wedge.
COMMANDS = (
    *(Command.follow(t, 0.9 * t.v_max_mps) for t in ROBOT.trajectories),
    Command.follow(T0, T0.v_max_mps),
    Command.follow(T0, T0.v_max_mps),
    Command.spin(1.0),
    Command.spin(-1.0),
    Command(-0.2, 0.0),
)


def world(name: str) -> WorldMap:
    return load_world(WORLDS / f"{name}.txt")


def generators(seeds: range) -> list[np.random.Generator]:
    return [np.random.default_rng(seed) for seed in seeds]


def assert_same(batch: RobotBatch, sims: list[Simulator]) -> None:
    """Every robot's truth, odometry, bump, clock and clearance, bit for bit."""
    assert batch.poses.tobytes() == np.array([s.pose for s in sims]).tobytes()
    assert batch.odometry == [s.odometry for s in sims]
    assert batch.bumped.tolist() == [s.bumped for s in sims]
    assert batch.time_s.tolist() == [s.time_s for s in sims]
    alone = np.array([s.clearance_m() for s in sims])
    assert batch.clearances_m().tobytes() == alone.tobytes()


def drive_both(
    batch: RobotBatch, sims: list[Simulator], steps: int, seed: int
) -> tuple[int, np.ndarray]:
    """Random commands, each held a second, to the batch and the lone robots alike, checked
    after every step; the bump count and the robots' clearances seen along the way."""
    rng = np.random.default_rng(seed)
    bumps = 0
    clearances = []
    for step in range(steps):
        if step % 10 == 0:
            commands = [COMMANDS[k] for k in rng.integers(len(COMMANDS), size=len(sims))]
        rings = batch.read_sonar()
        assert rings.tobytes() == np.array([s.read_sonar() for s in sims]).tobytes()
        batch.step(commands)
        for sim, command in zip(sims, commands, strict=True):
            sim.step(command)
        assert_same(batch, sims)
        bumps += int(batch.bumped.sum())
        clearances.append(batch.clearances_m())
    return bumps, np.array(clearances)


@pytest.mark.parametrize("name", ["lab", "square", "obstacles"])
def test_each_robot_moves_as_a_simulator_alone_bit_for_bit(name: str) -> None:
    w = world(name)
    batch = RobotBatch(w, ROBOT, generators(range(6)))
    sims = [Simulator(w, ROBOT, rng) for rng in generators(range(6))]
    bumps, clearances = drive_both(batch, sims, 300, seed=len(name))
    # The robots met walls and slid along them: touching for many steps, and moving meanwhile.
    assert bumps > 100
    assert (clearances == 0.0).sum() > 100


def test_robots_placed_and_restarted_go_on_as_simulators_alone() -> None:
    w = world("narrow")
    batch = RobotBatch(w, ROBOT, generators(range(4)))
    sims = [Simulator(w, ROBOT, rng) for rng in generators(range(4))]
    drive_both(batch, sims, 60, seed=1)
    for i, pose in enumerate([(1.0, 1.0, 0.5), (2.0, 1.2, -2.0)]):
        batch.place(i, *pose)
        sims[i].place(*pose)
    # A robot restarted is a new Simulator: at the start, its clock and contacts afresh.
    batch.restart(3, np.random.default_rng(99))
    sims[3] = Simulator(w, ROBOT, np.random.default_rng(99))
    assert_same(batch, sims)
    drive_both(batch, sims, 60, seed=2)


def test_one_robot_is_a_simulator() -> None:
    w = world("square")
    batch = RobotBatch(w, ROBOT, generators(range(1)))
    sims = [Simulator(w, ROBOT, np.random.default_rng(0))]
    bumps, _ = drive_both(batch, sims, 200, seed=3)
    assert bumps > 0


def test_robots_at_one_pose_never_touch_one_another() -> None:
    w = world("square")
    batch = RobotBatch(w, ROBOT, generators(range(5)))
    alone = Simulator(w, ROBOT, np.random.default_rng(0))
    assert not batch.bumped.any()
    for _ in range(10):  # straight ahead through the open middle of the square
        batch.step([Command.follow(T0, 0.3)] * 5)
        alone.step(Command.follow(T0, 0.3))
        assert not batch.bumped.any()
        assert (batch.poses == np.array(alone.pose)).all()


def test_a_command_for_each_robot_is_required() -> None:
    batch = RobotBatch(world("square"), ROBOT, generators(range(3)))
    with pytest.raises(ValueError, match="2 commands for 3 robots"):
        batch.step([Command.spin(1.0)] * 2)


def test_a_robot_sitting_a_step_out_keeps_its_clock_odometry_and_generator() -> None:
    w = world("square")
    batch = RobotBatch(w, ROBOT, generators(range(2)))
    sims = [Simulator(w, ROBOT, rng) for rng in generators(range(2))]
    drive_both(batch, sims, 5, seed=4)
    batch.step([Command.follow(T0, 0.3), None])
    sims[0].step(Command.follow(T0, 0.3))
    assert batch.time_s.tolist() == [sims[0].time_s, sims[1].time_s]
    assert batch.odometry == [sims[0].odometry, sims[1].odometry]
    assert batch.poses[1].tolist() == list(sims[1].pose)  # held still in open space
    drive_both(batch, sims, 20, seed=5)  # its noise goes on from the same draw


def test_a_robot_restarted_while_pushing_a_wall_starts_as_a_new_simulator() -> None:
    # pymunk keeps the solver's push out of a contact for the body's next step; a restarted
    # robot must not inherit it.
    w = world("square")
    batch = RobotBatch(w, ROBOT, generators(range(2)))
    sims = [Simulator(w, ROBOT, rng) for rng in generators(range(2))]
    full_ahead = [Command.follow(T0, T0.v_max_mps)] * 2
    while not batch.bumped.all():
        batch.step(full_ahead)
        for sim in sims:
            sim.step(full_ahead[0])
    batch.step([Command.follow(T0, T0.v_max_mps), None])
    sims[0].step(full_ahead[0])
    batch.restart(1, np.random.default_rng(7))
    sims[1] = Simulator(w, ROBOT, np.random.default_rng(7))
    assert_same(batch, sims)
    drive_both(batch, sims, 20, seed=6)


def test_rings_read_ahead_are_drawn_only_for_the_robots_that_take_them() -> None:
    w = world("lab")
    batch = RobotBatch(w, ROBOT, generators(range(3)))
    sims = [Simulator(w, ROBOT, rng) for rng in generators(range(3))]
    for step in range(30):
        batch.read_ahead(range(3))
        # Robot 0 reads its ring every step, robot 1 every other step, robot 2 never: each
        # as a Simulator asked as often, its generator drawn no further.
        for i in (0, 1) if step % 2 else (0,):
            assert batch.alone(i).read_sonar().tobytes() == sims[i].read_sonar().tobytes()
        batch.settle()
        commands = [Command.follow(T0, 0.3), Command.spin(1.0), Command.follow(T0, 0.2)]
        batch.step(commands)
        for sim, command in zip(sims, commands, strict=True):
            sim.step(command)
        assert_same(batch, sims)
    assert batch.alone(2).read_sonar().tobytes() == sims[2].read_sonar().tobytes()
    robot = batch.alone(1)
    assert (robot.time_s, robot.pose, robot.odometry) == (
        sims[1].time_s,
        sims[1].pose,
        sims[1].odometry,
    )
