"""tvl/SonarRing-v0 as a Gymnasium vector environment: N copies of its task in one world,
every robot stepped by one RobotBatch (one physics space, one ring kernel call a step).

Each copy follows the single environment's rules (gym.task) over a step engine of its own
(agent.engine) on its robot of the batch, which moves and judges it as the single
environment's engine does its Simulator, so copy i with seed s and the same actions gives
what `SonarRingEnv` reset with seed s gives, step by step, through Gymnasium's next-step
autoreset (as `SyncVectorEnv` over single environments runs them).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium
import numpy as np
from gymnasium.error import ResetNeeded
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from tvl_cli.agent.engine import StepEngine, hold_together, step_together
from tvl_cli.core.method import Method
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.gym.actions import DISCRETE
from tvl_cli.gym.task import (
    RobotEpisode,
    RobotTask,
    positive_int,
    reset_option,
    step_limit,
)
from tvl_cli.sim.batch import RobotBatch
from tvl_cli.sim.worldmap import WorldMap


class SonarRingVectorEnv(VectorEnv[np.ndarray, np.ndarray, np.ndarray]):
    """`num_envs` robots in one world, each on its own episode of the task.

    No robot sees or touches another. Each draws its noise from its own generator, seeded
    by `reset(seed=s)` with s + i for copy i (or a list of seeds, one a copy). An episode that
    ends is reset at the copy's next step, whose action is then ignored (reward 0).
    """

    # Gymnasium declares metadata on its VectorEnv as a mutable class default; typed as it is.
    metadata: dict[str, Any] = {  # noqa: RUF012
        "autoreset_mode": AutoresetMode.NEXT_STEP,
        "render_modes": [],
    }

    def __init__(
        self,
        num_envs: int = 1,
        world: str | Path | WorldMap = "square",
        task: str = "avoid",
        *,
        goal: tuple[float, float] | None = None,
        wall_distance_m: float | None = None,
        action_type: str = DISCRETE,
        speed_fraction: float | None = None,
        method: Method | str | Path | None = None,
        robot: RobotConfig | str | Path | None = None,
        max_episode_steps: int | None = None,
    ) -> None:
        """The single environment's arguments (SonarRingEnv), and `max_episode_steps`, after
        which an episode is truncated (none by default; `gymnasium.make_vec` passes the
        registered one, as `gymnasium.make` wraps the single environment in its TimeLimit)."""
        positive_int(num_envs, "num_envs")
        self.robot_task = RobotTask.of(
            world,
            task,
            goal=goal,
            wall_distance_m=wall_distance_m,
            speed_fraction=speed_fraction,
            method=method,
            action_type=action_type,
            robot=robot,
        )
        self.method = self.robot_task.method
        self.num_envs = num_envs
        self.max_episode_steps = step_limit(max_episode_steps)
        self.single_observation_space = self.robot_task.observation_space()
        self.single_action_space = self.robot_task.actions.space()
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self._rngs: list[np.random.Generator | None] = [None] * num_envs
        self._batch: RobotBatch | None = None
        self._engines: list[StepEngine] = []  # one a copy, over its robot of the batch
        self._episodes = [RobotEpisode(self.robot_task) for _ in range(num_envs)]
        self._elapsed = np.zeros(num_envs, dtype=np.int64)  # steps of each episode so far
        self._ended = np.zeros(num_envs, dtype=bool)  # to be reset at the next step

    def reset(
        self,
        *,
        seed: int | list[int | None] | None = None,
        options: dict[str, Any] | None = None,
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Every copy from the world's start. `seed`: s seeds copy i with s + i, a list one
        seed a copy; without one a copy goes on with its generator (a fresh one at first).
        With `options={"continue": True}`, every copy goes on from where its last episode
        ended instead, backed off 0.15 m along its path if it ended in a bump, as the
        single environment's reset with continue does."""
        going_on = reset_option(options)
        if going_on:
            if seed is not None:
                raise ValueError("a seed starts afresh: reset with continue takes none")
            if self._batch is None:
                raise ValueError("nothing to continue: reset() without it first")
            self._back_off(self._batch)
        else:
            self._start_afresh(self._seeds(seed))
        batch = self._running()
        self._elapsed[:] = 0
        self._ended[:] = False
        # Every copy's ring in one kernel call, each taken as its engine reads it.
        batch.read_ahead(range(self.num_envs))
        observations = []
        infos: dict[str, Any] = {}
        for i, (engine, episode) in enumerate(self._copies()):
            observation, info = episode.begin(engine, remember=going_on)
            observations.append(observation)
            infos = self._add_info(infos, info, i)
        return np.stack(observations), infos

    def _start_afresh(self, seeds: list[int | None]) -> None:
        """Every robot at the world's start, seeded as `reset` says."""
        for i, copy_seed in enumerate(seeds):
            if copy_seed is not None or self._rngs[i] is None:
                self._rngs[i] = seeding.np_random(copy_seed)[0]
        rngs = [rng for rng in self._rngs if rng is not None]
        if self._batch is None:
            batch = self._batch = RobotBatch(self.robot_task.world, self.robot_task.robot, rngs)
            self._engines = [self.robot_task.engine_over(batch.alone(i)) for i in range(len(rngs))]
        else:
            for i, rng in enumerate(rngs):
                self._batch.restart(i, rng)
                self._engines[i].go_on()

    def _back_off(self, batch: RobotBatch) -> None:
        """Each robot that ended in a bump driving forward backs off, as the single
        environment's does, through its engine; one with fewer back-off steps (or none) sits
        the others' out, held still (RobotBatch.step). Each then goes on from where it is, its
        judge afresh."""
        plans = [episode.backoff(engine.sim.bumped) for engine, episode in self._copies()]
        hold_together(batch, self._engines, plans)
        for engine in self._engines:
            engine.go_on()

    def step(
        self, actions: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        batch = self._running()
        actions = np.asarray(actions)
        shape = (self.num_envs, *(self.single_action_space.shape or ()))
        if actions.shape != shape:
            raise ValueError(
                f"actions of shape {actions.shape} for {shape} ({self.num_envs} copies)"
            )
        restarting = self._ended.copy()
        commands = [
            None if restarting[i] else episode.command(actions[i])
            for i, episode in enumerate(self._episodes)
        ]
        outcomes = step_together(batch, self._engines, commands)
        for k in np.flatnonzero(restarting).tolist():
            rng = self._rngs[k]
            assert rng is not None
            batch.restart(k, rng)  # a reset without a seed goes on with the generator
            self._engines[k].go_on()
        # Every copy's ring in one kernel call, each taken as its engine reads it.
        batch.read_ahead(range(self.num_envs))
        observations = []
        rewards = np.zeros(self.num_envs)
        terminations = np.zeros(self.num_envs, dtype=bool)
        infos: dict[str, Any] = {}
        for i, (engine, episode) in enumerate(self._copies()):
            outcome = outcomes[i]
            if outcome is None:
                observation, info = episode.begin(engine)
                self._elapsed[i] = 0
            else:
                observation, reward, terminated, info = episode.after(actions[i], outcome)
                rewards[i], terminations[i] = reward, terminated
                self._elapsed[i] += 1
            observations.append(observation)
            infos = self._add_info(infos, info, i)
        truncations = np.zeros(self.num_envs, dtype=bool)
        if self.max_episode_steps is not None:
            truncations = ~restarting & (self._elapsed >= self.max_episode_steps)
        self._ended = terminations | truncations
        return np.stack(observations), rewards, terminations, truncations, infos

    def _seeds(self, seed: object) -> list[int | None]:
        """A seed for each copy, checked as Gymnasium checks one: gymnasium.error.Error
        for what is not a whole number 0 or more, or a list of them (or None) one a copy."""
        if seed is None:
            return [None] * self.num_envs
        if isinstance(seed, int):
            seeds: list[object] = [seed + i for i in range(self.num_envs)]
        elif isinstance(seed, list | tuple):
            if len(seed) != self.num_envs:
                raise ValueError(f"{len(seed)} seeds for {self.num_envs} copies")
            seeds = list(seed)
        else:
            raise gymnasium.error.Error(
                f"Seed must be a python integer or a list of them, actual type: {type(seed)}"
            )
        for each in seeds:
            seeding.np_random(each)  # type: ignore[arg-type]  # Gymnasium's own refusals
        return seeds  # type: ignore[return-value]

    def _running(self) -> RobotBatch:
        if self._batch is None:
            raise ResetNeeded("call reset() before step()")
        return self._batch

    def _copies(self) -> list[tuple[StepEngine, RobotEpisode]]:
        """Each copy's engine and episode."""
        return list(zip(self._engines, self._episodes, strict=True))
