"""The one drive loop on a real simulated robot: what it measures, and what it counts."""

from __future__ import annotations

import math

import pytest

from tvl_cli.agent.drive import Step, drive
from tvl_cli.agent.policy import Decision, Observation
from tvl_cli.core.drive_command import Command
from tvl_cli.core.metrics import MetricsRecorder
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import parse_world

ROBOT = RobotConfig()
# A hall 7.5 m long with its north wall's face at y = 2.0 m and south wall's at y = 0.25 m.
HALL = parse_world(
    "version: 1\nname: hall\ncell: 0.25\n\n"
    + "#" * 32
    + "\n"
    + ("#" + "." * 30 + "#\n") * 2
    + "#.>"
    + "." * 28
    + "#\n"
    + ("#" + "." * 30 + "#\n") * 4
    + "#" * 32
    + "\n",
    "hall",
)
Y_M = 1.45  # the robot's centre: its edge 0.35 m from the north wall, 1.0 m from the south


class Scripted:
    """A policy that gives the commands it was handed, one a step, then stops."""

    def __init__(self, commands: list[Command]) -> None:
        self.commands = list(commands)

    def decide(self, obs: Observation) -> Decision:
        return Decision(self.commands.pop(0) if self.commands else Command(0.0, 0.0))

    def interrupt(self) -> None:
        self.commands = []


def hall_simulator(x: float, heading: float) -> Simulator:
    import numpy as np

    sim = Simulator(HALL, ROBOT, np.random.default_rng(0))
    sim.place(x, Y_M, heading)
    return sim


def scripted(sim: Simulator, commands: list[Command]):
    steps: list[Step] = []
    minutes = len(commands) * ROBOT.control_period_s / 60.0
    return drive(sim, Scripted(commands), minutes, on_step=steps.append), steps


def test_metrics_of_a_straight_run_beside_a_wall() -> None:
    # 10 steps spinning on the spot at 1 rad/s to face east, then 30 steps at 0.5 m/s east.
    sim = hall_simulator(2.0, -1.0)
    result, _ = scripted(sim, [Command.spin(1.0)] * 10 + [Command(0.5, 0.0)] * 30)
    assert result.sim_s == pytest.approx(4.0)
    assert result.distance_m == pytest.approx(1.5, abs=1e-6)
    assert result.mean_speed_mps == pytest.approx(1.5 / 4.0, abs=1e-6)
    assert result.mean_drive_speed_mps == pytest.approx(0.5, abs=1e-6)
    assert result.mean_clearance_m == pytest.approx(0.35, abs=1e-6)
    assert result.collisions == 0 and result.contacts == 0
    assert result.spins == 1 and result.backoffs == 0
    assert result.goal_reached is None and result.time_to_goal_s is None  # no goal sought


def test_pushing_into_a_wall_is_one_collision_however_long_it_lasts() -> None:
    sim = hall_simulator(4.0, math.pi / 2)  # facing the north wall 0.35 m away
    result, _ = scripted(sim, [Command(0.5, 0.0)] * 30)
    assert result.collisions == 1
    assert result.collisions_per_min == pytest.approx(1 / 0.05)
    # The approach through the blind zone ended touching: it counts once, as the collision.
    assert result.near_misses == 0 and result.contacts == 1
    # The body stops at the wall: it travelled the clearance and no further.
    assert result.distance_m == pytest.approx(0.35, abs=0.01)


def test_backing_off_and_hitting_again_is_a_second_collision_and_one_backoff() -> None:
    sim = hall_simulator(4.0, math.pi / 2)
    into, back = Command(0.5, 0.0), Command(-0.5, 0.0)
    result, steps = scripted(sim, [into] * 10 + [back] * 5 + [into] * 10)
    assert result.collisions == 2 and result.backoffs == 1
    assert [e for s in steps for e in s.events] == [
        "bump", "backoff", "backoff-end", "bump",
    ]  # fmt: skip


def test_an_approach_into_the_blind_zone_that_turns_away_is_a_near_miss() -> None:
    sim = hall_simulator(4.0, math.pi / 2)
    # 0.35 m to the wall: 0.25 m brings a front sonar inside its 0.15 m blind zone, untouched.
    result, steps = scripted(sim, [Command(0.5, 0.0)] * 6 + [Command.spin(1.0)] * 5)
    assert (result.collisions, result.near_misses, result.contacts) == (0, 1, 1)
    assert result.contacts_per_min == pytest.approx(1 / (11 * 0.1 / 60))
    # Judged when the approach ends: once the robot no longer drives on into the blind zone.
    assert [e for s in steps for e in s.events] == ["spin", "near-miss"]


def test_an_approach_still_open_when_the_run_ends_counts() -> None:
    sim = hall_simulator(4.0, math.pi / 2)
    result, _ = scripted(sim, [Command(0.5, 0.0)] * 6)
    assert result.near_misses == 1 and result.collisions == 0


def test_the_goal_is_judged_by_odometry_unless_told_otherwise() -> None:
    sim = hall_simulator(2.0, 0.0)
    metrics = drive(sim, Scripted([Command(0.5, 0.0)] * 40), 4.0 / 60.0, goal_xy=(3.0, Y_M))
    assert metrics.goal_reached
    assert metrics.time_to_goal_s == pytest.approx(1.5, abs=0.11)  # 0.3 m short of 3.0 m


def test_steps_that_look_at_nothing_read_no_sonar() -> None:
    # Spinning on the spot, nobody needs the ring: no sonar noise is drawn for it.
    sim = hall_simulator(2.0, 0.0)
    _, steps = scripted(sim, [Command.spin(1.0)] * 5)
    assert all(s.ring_m is None for s in steps)


def test_five_minutes_of_steps_are_exactly_five_minutes() -> None:
    # One collision in 3000 control steps of 0.1 s is 0.2 a minute, not a hair over.
    metrics = MetricsRecorder((0.0, 0.0))
    for step in range(3000):
        events = ("bump",) if step == 10 else ()
        metrics.record((0.0, 0.0), ROBOT.control_period_s, 0.5, False, False, events)
    result = metrics.result()
    assert result.sim_s == 300.0
    assert result.collisions_per_min == 0.2 and result.contacts_per_min == 0.2
