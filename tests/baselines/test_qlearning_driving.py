"""Q-learning driving the real simulator: punishment, backing off, determinism, competence."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tvl_cli.agent.policy import LazyRing, Observation
from tvl_cli.baselines.qlearning import QLearning, QPolicy, learn_and_evaluate
from tvl_cli.baselines.qtable import QParams, RuleStates
from tvl_cli.core.drive_command import Command
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.reward import forward_travel_m
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import load_world

WORLDS = Path(__file__).resolve().parents[2] / "worlds"
SQUARE = load_world(WORLDS / "square.txt")  # the east wall's inner face at x = 3.75
ROBOT = RobotConfig()
STATES = RuleStates(SINGLE.tables[0])
T0 = ROBOT.trajectory_index("T0")


def observe(sim: Simulator) -> Observation:
    return Observation(sim.time_s, LazyRing(sim.read_sonar), sim.odometry, sim.bumped)


def facing_the_east_wall(gap_m: float) -> Simulator:
    sim = Simulator(SQUARE, ROBOT, np.random.default_rng(0))
    sim.place(3.75 - ROBOT.radius_m - gap_m, 2.0, 0.0)
    return sim


def test_a_bump_is_punished_without_bootstrapping_and_followed_by_backing_off() -> None:
    params = QParams(epsilon=0.0)
    q = np.zeros((STATES.count, len(ROBOT.trajectories)))
    policy = QPolicy(q, STATES, ROBOT, params, np.random.default_rng(0))
    sim = facing_the_east_wall(0.03)
    before = sim.odometry
    command = policy.decide(observe(sim)).command  # unknown state: T0 at its top speed
    assert command == Command(0.6, 0.0)
    sim.step(command)
    assert sim.bumped
    backing = [policy.decide(observe(sim)).command for _ in range(3)]
    (punished,) = np.argwhere(q != 0)
    assert punished[1] == T0
    reward = forward_travel_m(before, sim.odometry) - params.collision_penalty
    assert q[tuple(punished)] == pytest.approx(params.learning_rate * reward)
    # 0.15 m back along the path at 0.06 m a control period: three periods.
    assert backing == [Command(-0.6, -0.0)] * 3


def test_progress_is_rewarded_with_the_next_state_bootstrapped() -> None:
    params = QParams(epsilon=0.0)
    q = np.zeros((STATES.count, len(ROBOT.trajectories)))
    policy = QPolicy(q, STATES, ROBOT, params, np.random.default_rng(0))
    sim = Simulator(SQUARE, ROBOT, np.random.default_rng(0))  # the start: 1.4 m of room ahead
    before = sim.odometry
    sim.step(policy.decide(observe(sim)).command)
    policy.decide(observe(sim))
    (updated,) = np.argwhere(q != 0)
    assert updated[1] == T0
    assert q[tuple(updated)] == pytest.approx(
        params.learning_rate * forward_travel_m(before, sim.odometry)
    )


def test_greedy_evaluation_leaves_the_table_alone() -> None:
    learner = QLearning(SQUARE, ROBOT, seed=2)
    learner.train(0.3)
    learnt = learner.q.copy()
    learner.evaluate(0.3, seed=2)
    np.testing.assert_array_equal(learner.q, learnt)


def test_the_same_seed_learns_the_same_table() -> None:
    first, second, other = (QLearning(SQUARE, ROBOT, seed) for seed in (4, 4, 5))
    runs = [learner.train(0.5) for learner in (first, second, other)]
    np.testing.assert_array_equal(first.q, second.q)
    assert runs[0] == runs[1]
    assert not np.array_equal(first.q, other.q)


def test_learning_counts_its_collisions() -> None:
    learner = QLearning(SQUARE, ROBOT, seed=1)
    runs = [learner.train(0.5) for _ in range(2)]
    assert learner.learn_collisions == sum(r.collisions for r in runs) > 0


@pytest.mark.slow  # over a second
def test_competence_is_judged_every_k_learning_minutes() -> None:
    result = learn_and_evaluate(SQUARE, ROBOT, 0.3, 0.2, seed=1, competence_every=0.1)
    minutes = [check.learn_minutes for check in result.checks]
    assert minutes == pytest.approx([0.1, 0.2, 0.3])
    # A third of a minute is not enough to learn: every check's greedy run pins itself to a
    # wall and barely moves, so none is competent and no time to competence is found.
    assert all(0 < check.mean_speed_mps < 0.3 for check in result.checks)
    assert not any(check.competent for check in result.checks)
    assert result.time_to_competence_min is None
    assert result.evaluation.sim_s == pytest.approx(12.0)


def test_a_greedy_run_backs_off_only_inside_the_bump_reflex() -> None:
    learner = QLearning(SQUARE, ROBOT, seed=1)
    learner.train(0.3)
    alone = learner.evaluate(0.5, seed=1)
    reflexed = learner.evaluate(0.5, seed=1, reflexes=("bump",))
    assert alone.collisions > 0 and alone.backoffs == 0
    assert reflexed.backoffs > 0
