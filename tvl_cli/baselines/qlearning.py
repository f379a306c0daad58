"""Tabular Q-learning over the single FAM's 720 rules: the reinforcement-learning alternative.

The state of a sonar ring is the rule that fires strongest for it; the actions are the 7
trajectories, each driven at its maximum velocity. Every control period earns the distance
the wheels report travelled forward, and a bump costs a fixed penalty and ends the episode,
after which the learner backs off along its path as TVL learning does. A greedy run backs
off only if a reflex says so, as a TVL run does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import pairwise

import numpy as np

from tvl_cli.agent.drive import StepSink, drive
from tvl_cli.agent.motions import backoff_commands
from tvl_cli.agent.policy import Decision, Observation
from tvl_cli.agent.reflexes import wrap
from tvl_cli.baselines.qtable import QParams, QTable, RuleStates
from tvl_cli.core.competence import COMPETENCE_RUN_MINUTES, is_competent
from tvl_cli.core.drive_command import Command
from tvl_cli.core.fam_config import SINGLE, FamTable
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.reward import step_reward
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.robot import Pose, Simulator
from tvl_cli.sim.worldmap import WorldMap

DEFAULT_Q = QParams()


def empty_table(
    robot: RobotConfig, params: QParams = DEFAULT_Q, table: FamTable = SINGLE.tables[0]
) -> QTable:
    """The baseline's Q-table before learning: a FAM table's rules as states (the single
    FAM's by default), the robot's trajectories as actions, every value zero."""
    return QTable(RuleStates(table), len(robot.trajectories), params)


class QPolicy:
    """Drives by a Q-table: epsilon-greedy and updating it while learning, greedy otherwise."""

    def __init__(
        self,
        q: np.ndarray,
        states: RuleStates,
        robot: RobotConfig,
        params: QParams,
        rng: np.random.Generator | None = None,
    ) -> None:
        """`q` (rules, trajectories) is learnt in place, shared with the owner; `rng` draws the
        exploration: without one the policy is greedy and never learns."""
        self.table = QTable(states, len(robot.trajectories), params, q)
        self.robot = robot
        self.params = params
        self.rng = rng
        self._actions = [Command.follow(t, t.v_max_mps) for t in robot.trajectories]
        self._queue: list[Command] = []  # backing off after a bump, while learning
        self._pending: tuple[int, int, Pose] | None = None  # state, action, odometry at choice

    def interrupt(self) -> None:
        # A reflex moved the robot: the last action's outcome is not its own to learn from.
        self._pending = None

    def decide(self, obs: Observation) -> Decision:
        if self._queue:
            return Decision(self._queue.pop())
        if self._pending is not None and obs.bumped and self.rng is not None:
            self._end_episode(obs, *self._pending)
            return Decision(self._queue.pop())
        state = self.table.state(obs.ring_m)
        if self._pending is not None and self.rng is not None:
            last_state, action, odometry = self._pending
            reward = step_reward(odometry, obs.odometry, False, self.params.collision_penalty)
            self.table.learn(last_state, action, reward, state)
        action = self.table.act(state, self.rng)
        self._pending = (state, action, obs.odometry)
        return Decision(self._actions[action], trajectory=action, choice=action)

    def _end_episode(self, obs: Observation, state: int, action: int, odometry: Pose) -> None:
        """Punish the action that bumped, with nothing after it, and back off along the arc."""
        reward = step_reward(odometry, obs.odometry, True, self.params.collision_penalty)
        self.table.learn(state, action, reward, None)
        self._pending = None
        self._queue = backoff_commands(self._actions[action], self.robot, self.params.reverse_m)


class QLearning:
    """A Q-table learnt by one robot driving in one world, and greedy runs that judge it.

    Learning continues where the last `train` call stopped: same robot, same table.
    """

    def __init__(
        self,
        world: WorldMap,
        robot: RobotConfig,
        seed: int,
        params: QParams = DEFAULT_Q,
        table: FamTable = SINGLE.tables[0],
    ) -> None:
        sim_seed, explore_seed = np.random.SeedSequence(seed).spawn(2)
        self.world = world
        self.robot = robot
        self.params = params
        learnt = empty_table(robot, params, table)
        self.states = learnt.states
        self.q = learnt.q  # (rules, trajectories)
        self._sim = Simulator(world, robot, np.random.default_rng(sim_seed))
        self._learner = QPolicy(
            self.q, self.states, robot, params, np.random.default_rng(explore_seed)
        )
        self.learn_collisions = 0

    def train(self, minutes: float) -> RunMetrics:
        """Learn for `minutes` of simulated time; the metrics of that stretch of driving."""
        metrics = drive(self._sim, self._learner, minutes, measure=False)
        self.learn_collisions += metrics.collisions
        return metrics

    def evaluate(
        self,
        minutes: float,
        seed: int,
        reflexes: tuple[str, ...] = (),
        on_step: StepSink | None = None,
    ) -> RunMetrics:
        """A greedy `avoid` run from the world's start without learning, seeded as `tvl run`
        is, inside the named reflexes."""
        sim = Simulator(self.world, self.robot, np.random.default_rng(seed))
        greedy_policy = QPolicy(self.q, self.states, self.robot, self.params)
        policy = wrap(greedy_policy, reflexes, self.robot, "avoid")
        return drive(sim, policy, minutes, on_step=on_step)


@dataclass(frozen=True, slots=True)
class CompetenceCheck:
    """A greedy `avoid` run after some minutes of learning."""

    learn_minutes: float
    contacts_per_min: float
    mean_speed_mps: float
    competent: bool


@dataclass(frozen=True, slots=True)
class QLearningResult:
    evaluation: RunMetrics  # the final greedy run
    learn_minutes: float
    learn_collisions: int
    checks: tuple[CompetenceCheck, ...]  # empty unless asked for

    @property
    def time_to_competence_min(self) -> float | None:
        """The first checked learning minute whose greedy run was competent."""
        return next((c.learn_minutes for c in self.checks if c.competent), None)


def learn_and_evaluate(
    world: WorldMap,
    robot: RobotConfig,
    learn_minutes: float,
    minutes: float,
    seed: int,
    competence_every: float | None = None,
    params: QParams = DEFAULT_Q,
    reflexes: tuple[str, ...] = (),
    on_step: StepSink | None = None,
) -> QLearningResult:
    """Learn for `learn_minutes` (0: not at all), judging competence every `competence_every`
    learning minutes until it is reached, then run the greedy policy for `minutes`; every
    greedy run inside the named reflexes, the last one's steps to `on_step`."""
    learner = QLearning(world, robot, seed, params)
    checks: list[CompetenceCheck] = []
    stretch = competence_every or learn_minutes
    stretches = math.ceil(learn_minutes / stretch - 1e-9) if learn_minutes > 0 else 0
    # Rounded so that 3 x 0.1 minutes reads 0.3, not 0.30000000000000004.
    ends = [min(round(k * stretch, 9), learn_minutes) for k in range(1, stretches + 1)]
    for start, end in pairwise([0.0, *ends]):
        learner.train(end - start)
        if competence_every is not None and not any(c.competent for c in checks):
            run = learner.evaluate(COMPETENCE_RUN_MINUTES, seed, reflexes)
            checks.append(
                CompetenceCheck(
                    end,
                    run.contacts_per_min,
                    run.mean_speed_mps,
                    is_competent(run),
                )
            )
    return QLearningResult(
        learner.evaluate(minutes, seed, reflexes, on_step),
        learn_minutes,
        learner.learn_collisions,
        tuple(checks),
    )
