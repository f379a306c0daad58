"""Agents over the environment's observations and actions, to compare learners against: the
paper's TVL policy over a FAM, and the Q-learning baseline's table learnt by stepping it.

Each is called with an observation and returns an action.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np

from tvl_cli.agent.policy import LazyRing, Observation
from tvl_cli.agent.tvl import TvlPolicy
from tvl_cli.baselines.qlearning import DEFAULT_Q, empty_table
from tvl_cli.baselines.qtable import QParams
from tvl_cli.core.behaviours import BEHAVIOUR_NAMES, DEFAULT_THRESHOLD, is_threshold
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.gym.actions import DISCRETE, ROBOT, SPIN_LEFT, SPIN_RIGHT
from tvl_cli.gym.task import AVOID, SONARS
from tvl_cli.io.famfile import read_fam


class TvlGymPolicy:
    """The paper's TVL choice rule (agent.tvl, no reflex) acting in the environment.

    It drives the trajectory it chooses at the environment's speed rather than at the
    velocity it perceives, and spins to face a view at the robot's spin rate, a step at a
    time: the nearest the discrete actions come to `tvl run --paper`.
    """

    def __init__(
        self, fam: Fam | str | Path, behaviour: str = "avoid", threshold: float = DEFAULT_THRESHOLD
    ) -> None:
        """`fam` a FAM or the path of a FAM file; `behaviour` one of `tvl run`'s (`goal`
        needs the `goal` task's observation)."""
        if behaviour not in BEHAVIOUR_NAMES:
            raise ValueError(
                f"unknown behaviour {behaviour!r} (choose from {', '.join(BEHAVIOUR_NAMES)})"
            )
        if not is_threshold(threshold):
            raise ValueError(f"threshold {threshold!r} is outside (0, 1]")
        if not isinstance(fam, Fam):
            try:
                fam = read_fam(fam).fam
            except BadInput as problem:
                raise ValueError(str(problem)) from None
        self.fam = fam
        self.behaviour = behaviour
        self.threshold = threshold
        self.reset()

    def reset(self) -> None:
        """Drop any plan under way (a spin to face a view): call it when the episode does."""
        self._policy = TvlPolicy(self.fam, ROBOT, self.behaviour, self.threshold)

    def __call__(self, obs: np.ndarray) -> int:
        ring_m = np.asarray(obs[:SONARS], dtype=np.float64)
        goal_xy = None
        if self.behaviour == "goal":
            if len(obs) < SONARS + 2:
                raise ValueError("the goal behaviour needs the goal task's observation")
            bearing, distance = float(obs[SONARS]), float(obs[SONARS + 1])
            # The observation gives the goal relative to the robot: the robot is put at the
            # origin facing +x, and the goal where the observation says.
            goal_xy = (distance * math.cos(bearing), distance * math.sin(bearing))
        # The paper's policy reads no clock and no bump sensor (those are the reflexes').
        obs_now = Observation(0.0, LazyRing(lambda: ring_m), (0.0, 0.0, 0.0), False, goal_xy)
        decision = self._policy.decide(obs_now)
        if decision.trajectory >= 0:
            return decision.trajectory
        # Not following a trajectory, the policy is spinning to face a view or to look round.
        return SPIN_LEFT if decision.command.angular_radps > 0 else SPIN_RIGHT


class QTableAgent:
    """The Q-learning baseline's own table (baselines.qlearning.empty_table: the single FAM's
    720 rules and the seven trajectories) and learner (baselines.qtable.QTable, whose choice
    and update these are), learnt by stepping an `avoid` environment of discrete actions;
    called, it acts greedily.

    Its learning settings are `params`'; the reward (core.reward, as the baseline's), the bump
    penalty and the back-off after a bump are the environment's, which are the baseline's
    defaults.
    """

    def __init__(self, params: QParams = DEFAULT_Q) -> None:
        self.params = params
        self.table = empty_table(ROBOT, params)

    @property
    def q(self) -> np.ndarray:
        """(rules, trajectories) the learnt action values."""
        return self.table.q

    def __call__(self, obs: np.ndarray) -> int:
        return self.table.act(self.table.state(obs[:SONARS]))

    def learn(self, env: gymnasium.Env[np.ndarray, Any], minutes: float, seed: int) -> int:
        """Learn for `minutes` of simulated time from the world's start, epsilon-greedy, going
        on after each bump from where it happened (as the baseline learns); the bumps met.

        `seed` seeds the environment and, apart from it, the exploration.
        """
        task = getattr(env.unwrapped, "robot_task", None)
        if task is None or task.task != AVOID or task.actions.action_type != DISCRETE:
            raise ValueError("Q-learning learns the avoid task of tvl/SonarRing-v0, discrete")
        env_seed, explore_seed = np.random.SeedSequence(seed).generate_state(2)
        explore = np.random.default_rng(explore_seed)
        obs, info = env.reset(seed=int(env_seed))
        table = self.table
        state = table.state(obs[:SONARS])
        bumps = 0
        period_s = ROBOT.control_period_s
        # Simulated time, as the baseline counts it: the back-offs take some of it.
        while round(info["time_s"] / period_s) < round(minutes * 60.0 / period_s):
            action = table.act(state, explore)
            obs, reward, terminated, truncated, info = env.step(action)
            after = table.state(obs[:SONARS])
            # A bump ends the episode: nothing is bootstrapped after it. A time limit does not.
            table.learn(state, action, float(reward), None if terminated else after)
            if terminated or truncated:
                bumps += terminated
                obs, info = env.reset(options={"continue": True})
                after = table.state(obs[:SONARS])
            state = after
        return bumps
