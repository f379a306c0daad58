"""The step engine on real worlds: what reset and step return, what they judge, what they
leave unread; and every drive through it step for step as before it existed."""

from __future__ import annotations

import hashlib
import math
from dataclasses import asdict
from pathlib import Path

import numpy as np
import pytest

from tvl_cli.agent.drive import drive
from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.engine import GOAL_RADIUS_M, StepEngine, within_goal
from tvl_cli.agent.policy import Decision, Observation
from tvl_cli.agent.trace import Columns, TraceRecorder
from tvl_cli.baselines.dwa import MAP, RING, run_dwa
from tvl_cli.baselines.qlearning import learn_and_evaluate
from tvl_cli.commands.train import train_from_logs
from tvl_cli.core.contacts import BUMP, SPIN
from tvl_cli.core.drive_command import Command
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.labels import BUMP_LABELS
from tvl_cli.core.memory import NONE, PATCHES, MemoryChoice, MemoryConfig
from tvl_cli.core.method import DEFAULT_REFLEXES, Method, MethodChoice
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap, load_world

ROOT = Path(__file__).resolve().parents[2]
ROBOT = RobotConfig()


def world(name: str) -> WorldMap:
    return load_world(ROOT / "worlds" / f"{name}.txt")


SQUARE = world("square")  # start (2.125, 2.125) facing +x; the east wall's face at x = 3.75


def test_reset_puts_the_robot_at_the_start_and_reads_nothing_yet() -> None:
    engine = StepEngine(SQUARE, ROBOT)
    obs = engine.reset(1)
    assert (obs.time_s, obs.odometry, obs.bumped) == (0.0, SQUARE.start, False)
    assert obs.ring.value is None  # read on first use
    ring = obs.ring_m
    assert ring.shape == (16,) and ring[0] == pytest.approx(3.75 - 2.125 - ROBOT.radius_m, abs=0.1)


def test_a_seed_and_its_generator_give_the_same_steps() -> None:
    def steps(seed: int | np.random.Generator) -> list[tuple]:
        engine = StepEngine(SQUARE, ROBOT)
        seen = [tuple(engine.reset(seed).ring_m)]
        for command in [Command(0.5, 0.2)] * 5 + [Command.spin(1.0)] * 3:
            outcome = engine.step(command)
            seen.append((outcome.truth.pose, outcome.observation.odometry))
            seen.append(tuple(outcome.observation.ring_m))
        return seen

    assert steps(4) == steps(np.random.default_rng(4))
    assert steps(4) != steps(5)


def test_a_step_returns_the_observation_events_truth_and_done() -> None:
    engine = StepEngine(SQUARE, ROBOT, measure=True)
    before = engine.reset(1)
    outcome = engine.step(Command(0.5, 0.0))
    assert outcome.ring_m is None  # nothing looked at the ring before this first step
    assert outcome.truth.pose == pytest.approx((2.175, 2.125, 0.0))
    assert outcome.truth.clearance_m == pytest.approx(3.75 - 2.175 - ROBOT.radius_m)
    after = outcome.observation
    assert after is engine.observation and after.time_s == pytest.approx(0.1)
    assert after.odometry != before.odometry and not after.bumped
    assert outcome.events == () and not outcome.done
    # Driving on, the next step's near-miss test needs the ring before it: the engine reads it.
    assert engine.step(Command(0.5, 0.0)).ring_m is not None


def test_pushing_into_the_wall_is_one_bump_and_spinning_reads_nothing() -> None:
    engine = StepEngine(SQUARE, ROBOT)
    engine.reset(1)
    events = [engine.step(Command(0.6, 0.0)).events for _ in range(40)]
    assert [e for step in events for e in step] == [BUMP]
    assert engine.observation.bumped
    spins = [engine.step(Command.spin(1.0)) for _ in range(3)]
    assert spins[0].events == (SPIN,)
    # The last forward step's ring was read for its near-miss test; after it nobody looks.
    assert spins[0].ring_m is not None and all(s.ring_m is None for s in spins[1:])


def test_the_goal_is_done_within_its_radius_by_odometry_or_by_the_truth() -> None:
    goal = (3.0, 2.125)
    for by_odometry in (True, False):
        engine = StepEngine(SQUARE, ROBOT, goal_xy=goal, goal_by_odometry=by_odometry)
        assert engine.reset(1).goal_xy == goal
        outcomes = []
        while not (outcomes and outcomes[-1].done) and len(outcomes) < 30:
            outcomes.append(engine.step(Command(0.5, 0.0)))
        for outcome in outcomes:
            where = outcome.observation.odometry if by_odometry else outcome.truth.pose
            assert outcome.done == within_goal(where[:2], goal)
        # 0.875 m away at 0.05 m a step: done once within 0.3 m.
        assert outcomes[-1].done and len(outcomes) == math.ceil((0.875 - GOAL_RADIUS_M) / 0.05)


def test_over_goes_on_from_where_a_simulator_is_and_go_on_judges_afresh() -> None:
    sim = Simulator(SQUARE, ROBOT, np.random.default_rng(0))
    sim.place(3.0, 2.125, 0.0)
    engine = StepEngine.over(sim)
    assert engine.observation.odometry == (3.0, 2.125, 0.0)
    bumps = [e for _ in range(20) for e in engine.step(Command(0.6, 0.0)).events]
    assert bumps == [BUMP]
    engine.step(Command(-0.6, 0.0))
    engine.go_on()
    # A fresh judge has seen no back-off to end and no bump under way.
    assert engine.step(Command(0.6, 0.0)).events == (BUMP,)


def test_an_engine_not_reset_refuses_to_step() -> None:
    with pytest.raises(RuntimeError, match="reset the engine"):
        StepEngine(SQUARE, ROBOT).step(Command(0.1, 0.0))


# Digests of each drive's trace and metrics, recorded from the drive loop as it was before it
# ran over the step engine: every drive must give what it gave, bit for bit. Recorded again
# when the example log was learnt again by heard labels, after the code of the day had given
# every earlier digest from the earlier log.
@pytest.fixture(scope="module")
def square_fam() -> Fam:
    """The single FAM trained from the example log of learning in the square, labelling the
    driven trajectories alone, braking at 0.1 m/s² and capped at the top speed, as it was
    when the digests were recorded."""
    labels = (("labels", BUMP_LABELS), ("decel_mps2", 0.1), ("label_ceiling", 1.0))
    live_ring = MethodChoice(memory=MemoryChoice(NONE), settings=labels)
    return train_from_logs([ROOT / "logs" / "square-s1.h5"], SINGLE, live_ring).fam


def digest(chunks: list[Columns], metrics: RunMetrics) -> str:
    h = hashlib.sha256()
    for chunk in chunks:
        for key in sorted(chunk):
            h.update(key.encode())
            h.update(np.ascontiguousarray(chunk[key]).tobytes())
    # A run that sought no goal now says so (None); it said False when these were recorded.
    h.update(repr({**asdict(metrics), "goal_reached": bool(metrics.goal_reached)}).encode())
    return h.hexdigest()[:16]


@pytest.mark.parametrize(
    ("name", "behaviour", "seed", "reflexes", "memory", "expected"),
    [
        ("square", "avoid", 1, DEFAULT_REFLEXES, NONE, "66b2eb63d4e21aec"),
        ("lab", "avoid", 2, DEFAULT_REFLEXES, NONE, "d509fe8e9fc28056"),
        ("obstacles", "goal", 3, DEFAULT_REFLEXES, NONE, "f9db25014f300035"),
        ("corridor", "wall-left", 4, (), NONE, "536b2cda22368131"),
        ("lab", "avoid", 5, DEFAULT_REFLEXES, PATCHES, "54dc12a98f69940e"),
    ],
)
def test_a_run_gives_the_trace_it_gave_before_the_engine(
    square_fam: Fam,
    name: str,
    behaviour: str,
    seed: int,
    reflexes: tuple[str, ...],
    memory: str,
    expected: str,
) -> None:
    where = world(name)
    chunks: list[Columns] = []
    recorder = TraceRecorder(reflexes, ROBOT.sonar.count, [chunks.append])
    metrics = behave(
        where,
        ROBOT,
        square_fam,
        behaviour,
        minutes=0.5,
        seed=seed,
        threshold=0.85,
        goal_xy=where.goals[0] if behaviour == "goal" else None,
        method=Method(reflexes=reflexes, memory=MemoryConfig(memory)),
        on_step=recorder,
    )
    recorder.close()
    assert sum(len(chunk["pose"]) for chunk in chunks) == 300
    assert digest(chunks, metrics) == expected


@pytest.mark.slow  # over a second
def test_q_learning_learns_and_runs_as_before_the_engine() -> None:
    chunks: list[Columns] = []
    recorder = TraceRecorder(("bump",), ROBOT.sonar.count, [chunks.append])
    result = learn_and_evaluate(
        world("circle"), ROBOT, 1.0, 0.5, 7, competence_every=0.5, reflexes=("bump",),
        on_step=recorder,
    )  # fmt: skip
    recorder.close()
    assert result.learn_collisions == 70
    assert [c.contacts_per_min for c in result.checks] == [59.6, 99.2]
    assert digest(chunks, result.evaluation) == "a499b995a305bde5"


@pytest.mark.parametrize(
    ("sensor", "expected"), [(MAP, "e2391d8cbe6b5abe"), (RING, "e243fc390f1b35c0")]
)
def test_dwa_drives_as_before_the_engine(sensor: str, expected: str) -> None:
    where = world("obstacles")
    chunks: list[Columns] = []
    recorder = TraceRecorder((), ROBOT.sonar.count, [chunks.append])
    metrics = run_dwa(where, ROBOT, 0.5, 8, goal_xy=where.goals[0], on_step=recorder, sensor=sensor)
    recorder.close()
    assert digest(chunks, metrics) == expected


class Straight:
    """A policy that drives straight on at 0.2 m/s."""

    def decide(self, obs: Observation) -> Decision:
        return Decision(Command(0.2, 0.0))

    def interrupt(self) -> None:
        pass


def test_drive_over_a_simulator_goes_on_where_the_last_drive_stopped() -> None:
    # Learning drives one simulator in stretches: each starts where and when the last ended.
    sim = Simulator(SQUARE, ROBOT, np.random.default_rng(2))
    drive(sim, Straight(), 0.05, measure=False)
    assert sim.pose[0] == pytest.approx(2.125 + 0.6)
    second = drive(sim, Straight(), 0.05, measure=False)
    assert sim.time_s == pytest.approx(6.0) and sim.pose[0] == pytest.approx(2.125 + 1.2)
    assert second.distance_m == pytest.approx(0.6) and second.sim_s == pytest.approx(3.0)
