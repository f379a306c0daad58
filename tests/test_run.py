"""Run metrics on a real simulated robot, and runs that repeat exactly."""

from __future__ import annotations

import math
from dataclasses import asdict

import numpy as np
import pytest

from tvl_cli.core.command import Command
from tvl_cli.core.config import SINGLE, RobotConfig
from tvl_cli.core.fam import Fam
from tvl_cli.core.metrics import MetricsRecorder
from tvl_cli.learn import Learner, LearnParams
from tvl_cli.run import BLOCKED_S, Runner, RunParams, StepRecord
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap, parse_world
from tvl_cli.training import TrainParams

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


def drive(sim: Simulator, commands: list[Command]) -> MetricsRecorder:
    """Step the simulator through `commands`, feeding a recorder the true state each step."""
    metrics = MetricsRecorder(sim.pose[:2])
    for command in commands:
        sim.step(command)
        metrics.record(sim.pose[:2], ROBOT.control_period_s, sim.bumped, sim.clearance_m(), True)
    return metrics


def hall_simulator(x: float, heading: float) -> Simulator:
    sim = Simulator(HALL, ROBOT, np.random.default_rng(0))
    sim.place(x, Y_M, heading)
    return sim


def test_metrics_of_a_straight_run_beside_a_wall() -> None:
    # 10 steps spinning on the spot at 1 rad/s to face east, then 30 steps at 0.5 m/s east.
    sim = hall_simulator(2.0, -1.0)
    commands = [Command.spin(1.0)] * 10 + [Command(0.5, 0.0)] * 30
    result = drive(sim, commands).result()
    assert result.sim_s == pytest.approx(4.0)
    assert result.distance_m == pytest.approx(1.5, abs=1e-6)
    assert result.mean_speed_mps == pytest.approx(1.5 / 4.0, abs=1e-6)
    assert result.mean_clearance_m == pytest.approx(0.35, abs=1e-6)
    assert result.mean_wall_clearance_m == pytest.approx(0.35, abs=1e-6)
    assert result.collisions == 0
    assert result.goal_reached is False and result.time_to_goal_s is None


def test_pushing_into_a_wall_is_one_collision_however_long_it_lasts() -> None:
    sim = hall_simulator(4.0, math.pi / 2)  # facing the north wall 0.35 m away
    result = drive(sim, [Command(0.5, 0.0)] * 30).result()
    assert result.collisions == 1
    assert result.collisions_per_min == pytest.approx(1 / 0.05)
    # The body stops at the wall: it travelled the clearance and no further.
    assert result.distance_m == pytest.approx(0.35, abs=0.01)


def test_backing_off_and_hitting_again_is_a_second_collision() -> None:
    sim = hall_simulator(4.0, math.pi / 2)
    into, back = Command(0.5, 0.0), Command(-0.5, 0.0)
    result = drive(sim, [into] * 10 + [back] * 5 + [into] * 10).result()
    assert result.collisions == 2


def learnt_fam(world: WorldMap) -> Fam:
    fam = Fam(SINGLE, [t.name for t in ROBOT.trajectories])
    learner = Learner(world, ROBOT, fam, LearnParams(minutes=2.0), TrainParams(), seed=3)
    learner.run(lambda _episode: None, lambda _minute: None)
    return fam


@pytest.mark.parametrize("behaviour", ["avoid", "wall-left", "goal"])
def test_the_same_world_seed_and_options_give_the_same_run(behaviour: str) -> None:
    fam = learnt_fam(HALL)
    params = RunParams(behaviour, 0.85, 0.5, (6.0, 1.0) if behaviour == "goal" else None)
    first = Runner(HALL, ROBOT, fam, params, seed=5).run()
    second = Runner(HALL, ROBOT, fam, params, seed=5).run()
    assert asdict(first.metrics) == asdict(second.metrics)
    assert first.path == second.path
    assert first.metrics.distance_m > 1.0  # the robot went somewhere


def test_another_seed_gives_another_run() -> None:
    fam = learnt_fam(HALL)
    params = RunParams("avoid", 0.85, 0.5)
    first = Runner(HALL, ROBOT, fam, params, seed=5).run()
    second = Runner(HALL, ROBOT, fam, params, seed=6).run()
    assert first.path != second.path


def fast_everywhere_fam() -> Fam:
    """A FAM that perceives every trajectory at its maximum, whatever the ring reads."""
    return Fam(SINGLE, [t.name for t in ROBOT.trajectories], max(ROBOT.v_max_mps))


# A straight passage 7 m long and 0.75 m wide, the robot in its middle facing along it.
PASSAGE = parse_world(
    "version: 1\nname: passage\ncell: 0.25\n\n"
    + "#" * 30
    + "\n"
    + ("#" + "." * 28 + "#\n")
    + ("#.>" + "." * 26 + "#\n")
    + ("#" + "." * 28 + "#\n")
    + "#" * 30
    + "\n",
    "passage",
)


# Straight down the hall at T0's 0.6 m/s, the body's edge meets the east wall after 11.5 s.
TO_THE_END_WALL_MIN = 12.0 / 60.0


def test_a_wall_entering_the_blind_zone_ahead_is_backed_off_before_contact() -> None:
    params = RunParams("avoid", 0.85, TO_THE_END_WALL_MIN)
    result = Runner(HALL, ROBOT, fast_everywhere_fam(), params, seed=1).run()
    assert result.near_misses == 1
    assert result.metrics.collisions == 0


def test_without_the_near_miss_back_off_the_same_run_meets_the_wall() -> None:
    params = RunParams("avoid", 0.85, TO_THE_END_WALL_MIN, near_miss_backoff=False)
    result = Runner(HALL, ROBOT, fast_everywhere_fam(), params, seed=1).run()
    assert result.near_misses == 0
    assert result.metrics.collisions == 1


def test_walls_alongside_in_a_narrow_passage_are_no_near_miss() -> None:
    # 0.75 m wide: 0.175 m either side of the body, just outside the sonars' blind zone.
    params = RunParams("avoid", 0.85, 5.0 / 60.0)
    result = Runner(PASSAGE, ROBOT, fast_everywhere_fam(), params, seed=1).run()
    assert result.near_misses == 0
    assert result.metrics.collisions == 0
    assert result.metrics.distance_m == pytest.approx(0.6 * 5.0, abs=0.01)


def test_after_a_near_miss_the_robot_sets_off_away_from_the_way_it_met_the_wall() -> None:
    steps: list[StepRecord] = []
    params = RunParams("avoid", 0.85, TO_THE_END_WALL_MIN + 2.0 / 60.0)
    result = Runner(HALL, ROBOT, fast_everywhere_fam(), params, seed=1).run(steps.append)
    assert result.near_misses >= 1
    reversing = next(i for i, s in enumerate(steps) if s.speed_mps < 0)
    after = next(s for s in steps[reversing:] if s.speed_mps > 0)
    # Every trajectory is fast, yet the robot (which met the wall driving east, heading 0)
    # turns on the spot until what it follows sets off more than 45 degrees away from east.
    assert abs(math.remainder(after.pose[2], 2 * math.pi)) > math.radians(40)


def test_a_near_miss_blocks_the_way_by_odometry_until_two_seconds_after_backing_off() -> None:
    steps: list[StepRecord] = []
    params = RunParams("avoid", 0.85, TO_THE_END_WALL_MIN)
    runner = Runner(HALL, ROBOT, fast_everywhere_fam(), params, seed=1)
    runner.run(steps.append)
    event = next(i for i, s in enumerate(steps) if s.speed_mps < 0)  # the first reversing step
    reversing = sum(1 for s in steps[event:] if s.speed_mps < 0)
    (way,) = runner.blocked_ways
    before = steps[event - 1]  # the step that drove into the blind zone
    assert way.heading_rad == before.odometry[2] != before.pose[2]
    dt = ROBOT.control_period_s
    assert way.until_s == pytest.approx(event * dt + reversing * dt + BLOCKED_S)


def test_five_minutes_of_steps_are_exactly_five_minutes() -> None:
    # One collision in 3000 control steps of 0.1 s is 0.2 a minute, not a hair over.
    metrics = MetricsRecorder((0.0, 0.0))
    for step in range(3000):
        metrics.record((0.0, 0.0), ROBOT.control_period_s, step == 10, 0.5, False)
    result = metrics.result()
    assert result.sim_s == 300.0
    assert result.collisions_per_min == 0.2
