"""One robot's part of the Gymnasium task, whatever steps its simulator: the command an action
asks for, and after the physics what the robot observes, its reward, whether the episode has
ended and the truth beside it. SonarRingEnv runs one over a Simulator; SonarRingVectorEnv
runs one a robot over a RobotBatch, so both follow the same rules.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from gymnasium import spaces

from tvl_cli.agent.engine import GOAL_RADIUS_M
from tvl_cli.agent.perception import Perception
from tvl_cli.agent.tvl import goal_bearing
from tvl_cli.baselines.qlearning import DEFAULT_Q, step_reward
from tvl_cli.core.behaviours import is_threshold
from tvl_cli.core.command import STOP, Command
from tvl_cli.core.config import RobotConfig
from tvl_cli.core.contacts import EventDetector, near_miss_sonars
from tvl_cli.core.errors import BadInput
from tvl_cli.core.memory import MemoryConfig
from tvl_cli.sim.motion import Pose
from tvl_cli.sim.worldgen import bundled_world_path
from tvl_cli.sim.worldmap import WorldMap, check_goal, load_world

TASKS = ("avoid", "goal")
ROBOT = RobotConfig()  # the robot of `tvl run`, with the real (noisy, specular) sonar ring
SONARS = ROBOT.sonar.count
# Actions 0-6 are the trajectories T3L..T3R; then a spin on the spot each way, and a stop.
SPIN_LEFT = len(ROBOT.trajectories)
SPIN_RIGHT = SPIN_LEFT + 1
STOP_ACTION = SPIN_LEFT + 2
ACTION_NAMES = (*(t.name for t in ROBOT.trajectories), "spin-left", "spin-right", "stop")


def resolve_world(world: str | Path | WorldMap) -> WorldMap:
    """A world map as given; else the text map at that path, or the bundled world of that
    name when no such file exists and the name has no extension. ValueError if neither."""
    if isinstance(world, WorldMap):
        return world
    path = Path(world)
    try:
        return load_world(path if path.is_file() or path.suffix else bundled_world_path(str(path)))
    except BadInput as problem:
        raise ValueError(str(problem)) from None


@dataclass(frozen=True, slots=True, eq=False)
class RobotTask:
    """What each robot is asked: its world, the task, the commands its actions stand for and
    how it perceives (the echo memory)."""

    world: WorldMap
    task: str  # one of TASKS
    goal_xy: tuple[float, float] | None  # metres; the `goal` task's only
    commands: tuple[Command, ...]  # by action
    memory: MemoryConfig
    # Odometry drifts, so its distance to the goal has no bound of its own: the world's
    # diagonal is as far as two points of the world can be, and the distance is capped there.
    far_m: float

    @classmethod
    def of(
        cls,
        world: str | Path | WorldMap,
        task: str,
        goal: tuple[float, float] | None,
        speed_fraction: float,
        memory: MemoryConfig | str,
    ) -> RobotTask:
        """The task from the environments' arguments (SonarRingEnv documents them); a
        ValueError names what is wrong."""
        if task not in TASKS:
            raise ValueError(f"unknown task {task!r} (choose from {', '.join(TASKS)})")
        if not is_threshold(speed_fraction):
            raise ValueError(f"speed_fraction {speed_fraction!r} is outside (0, 1]")
        resolved = resolve_world(world)
        try:
            remembering = memory if isinstance(memory, MemoryConfig) else MemoryConfig(memory)
        except BadInput as problem:
            raise ValueError(str(problem)) from None
        commands = (
            *(Command.follow(t, speed_fraction * t.v_max_mps) for t in ROBOT.trajectories),
            Command.spin(ROBOT.spin_rate_radps),
            Command.spin(-ROBOT.spin_rate_radps),
            STOP,
        )
        far_m = math.hypot(resolved.width_m, resolved.height_m)
        goal_xy = _goal(resolved, task, goal)
        return cls(resolved, task, goal_xy, commands, remembering, far_m)

    def observation_space(self) -> spaces.Box:
        low, high = [ROBOT.sonar.min_range_m] * SONARS, [ROBOT.sonar.max_range_m] * SONARS
        if self.goal_xy is not None:
            low, high = [*low, -math.pi, 0.0], [*high, math.pi, self.far_m]
        return spaces.Box(
            np.array(low, dtype=np.float32), np.array(high, dtype=np.float32), dtype=np.float32
        )

    def action_space(self) -> spaces.Discrete:
        return spaces.Discrete(len(self.commands))

    def goal_m(self, odometry: Pose) -> float:
        """Metres from the odometry's position to the goal."""
        assert self.goal_xy is not None
        return math.dist(odometry[:2], self.goal_xy)


def _goal(
    world: WorldMap, task: str, goal: tuple[float, float] | None
) -> tuple[float, float] | None:
    if task != "goal":
        if goal is not None:
            raise ValueError("goal is for task 'goal' only")
        return None
    if goal is not None:
        x, y = goal
        try:
            check_goal(world, x, y, where=f"goal {x:g},{y:g}")
        except BadInput as problem:
            raise ValueError(str(problem)) from None
        return (x, y)
    if not world.goals:
        raise ValueError(f"{world.name}: world has no goal; give one with goal=(x, y)")
    return world.goals[0]


@dataclass(frozen=True, slots=True)
class RobotNow:
    """What the simulator says of one robot after a step (or a reset)."""

    time_s: float
    pose: Pose  # the truth
    odometry: Pose
    bumped: bool


class RobotEpisode:
    """One robot's episode of a task: its perception, contact events, rewards and end.

    Fed in order: `begin` after the robot is (re)set, then for each step `command` before
    the physics and `after` with the ring read after it.
    """

    def __init__(self, task: RobotTask) -> None:
        self.task = task
        self.ring = np.empty(SONARS)  # (16,) metres read after the last step
        self.last: tuple[int, float, tuple[str, ...]] | None = None  # action, reward, events
        self.trail: list[tuple[float, float]] = []  # true positions this episode, metres
        self._perception = Perception(task.memory, ROBOT)
        self._events = EventDetector(near_miss_sonars(SONARS), ROBOT.sonar.min_range_m)
        self._odometry: Pose = task.world.start
        self._command = STOP

    def begin(
        self, ring: np.ndarray, now: RobotNow, remember: bool = False
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """A new episode from where the robot is: the observation and info. `remember`: a
        robot going on keeps what it heard; one starting afresh has heard nothing."""
        if not remember:
            self._perception = Perception(self.task.memory, ROBOT)
        self._events = EventDetector(near_miss_sonars(SONARS), ROBOT.sonar.min_range_m)
        perceived = self._sense(ring, now)
        self.last = None
        self.trail = [now.pose[:2]]
        return self._observation(perceived, now), self._info(now, ())

    def command(self, action: int) -> Command:
        """The command of an action, for the physics to hold for a step."""
        self._command = self.task.commands[action]
        return self._command

    def after(
        self, action: int, ring: np.ndarray, now: RobotNow
    ) -> tuple[np.ndarray, float, bool, dict[str, Any]]:
        """After the physics of a step: observation, reward, terminated and info."""
        before = self._odometry
        events = self._events.step(self.ring, self._command, now.bumped, False)
        perceived = self._sense(ring, now)
        task = self.task
        if task.goal_xy is None:
            reward = step_reward(before, now.odometry, now.bumped)
            terminated = now.bumped
        else:
            progress_m = task.goal_m(before) - task.goal_m(now.odometry)
            reward = progress_m - (DEFAULT_Q.collision_penalty if now.bumped else 0.0)
            terminated = now.bumped or task.goal_m(now.odometry) <= GOAL_RADIUS_M
        self.last = (action, reward, events)
        self.trail.append(now.pose[:2])
        return self._observation(perceived, now), reward, terminated, self._info(now, events)

    def _sense(self, ring: np.ndarray, now: RobotNow) -> np.ndarray:
        """Take the ring read where the robot is; what perception makes of it."""
        self.ring = ring
        self._odometry = now.odometry
        return self._perception.sense(now.time_s, now.odometry, ring)

    def _observation(self, perceived: np.ndarray, now: RobotNow) -> np.ndarray:
        """(16,) float32 metres, S0 forward, CCW (the echo memory's virtual ring with a
        memory); seeking a goal (18,): then its bearing (radians, left positive) and distance
        (metres), both by odometry."""
        task = self.task
        if task.goal_xy is None:
            return perceived.astype(np.float32)
        bearing = goal_bearing(now.odometry, task.goal_xy)
        distance = min(task.goal_m(now.odometry), task.far_m)
        return np.array([*perceived, bearing, distance], dtype=np.float32)

    def _info(self, now: RobotNow, events: tuple[str, ...]) -> dict[str, Any]:
        """The truth beside the observation: simulated time, true pose and odometry (x, y
        metres, heading radians, not wrapped), the bump sensor, and the contact events
        (core.contacts) the step began."""
        info = {
            "time_s": now.time_s,
            "pose": np.array(now.pose),
            "odometry": np.array(now.odometry),
            "bumped": now.bumped,
            "events": events,
        }
        if self.task.goal_xy is not None:
            info["goal_reached"] = self.task.goal_m(now.odometry) <= GOAL_RADIUS_M
        return info
