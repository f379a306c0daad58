"""One robot's part of the Gymnasium task, over the step engine (agent.engine) that moves and
judges it: the command an action asks for, and after the step what the robot observes, its
reward, whether the episode has ended and the truth beside it. SonarRingEnv runs one over a
lone engine; SonarRingVectorEnv runs one a robot, over an engine each on a RobotBatch's
robots, so both follow the same rules.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from gymnasium import spaces

from tvl_cli.agent.engine import StepEngine, StepOutcome, within_goal
from tvl_cli.agent.motions import backoff_commands
from tvl_cli.agent.perception import Perception
from tvl_cli.core.angles import goal_bearing
from tvl_cli.core.contacts import drives_forward
from tvl_cli.core.drive_command import STOP, Command
from tvl_cli.core.errors import BadInput
from tvl_cli.core.learn_params import BACKOFF_M
from tvl_cli.core.memory import MemoryConfig
from tvl_cli.core.method import DEFAULT, Method
from tvl_cli.core.reward import bump_penalty_m, step_reward
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.gym.actions import DISCRETE, ROBOT, Actions, is_real
from tvl_cli.io.methodfile import resolve_method as resolve_named_method
from tvl_cli.io.robotfile import resolve_robot as resolve_named_robot
from tvl_cli.sim.batch import BatchRobot
from tvl_cli.sim.motion import Pose
from tvl_cli.sim.worldgen import bundled_world_path
from tvl_cli.sim.worldmap import WorldMap, check_goal, load_world

AVOID, GOAL, WALL = "avoid", "goal", "wall"
TASKS = (AVOID, GOAL, WALL)
SONARS = ROBOT.sonar.count
# The wall task's distance, body edge to the nearest obstacle: about what the paper's wall
# following keeps at threshold 0.85 (docs/results.md, *Figure 21*: 0.40 m in the square).
WALL_DISTANCE_M = 0.4
# Each metre off that distance costs this much reward a step: at the top speed (0.06 m a step)
# a robot 0.6 m off earns nothing for its progress, and one standing still pays for its error.
WALL_ERROR_WEIGHT = 0.1


def resolve_world(world: str | Path | WorldMap) -> WorldMap:
    """A world map as given; else the text map at that path, or the bundled world of that
    name when no such file exists and the name has no extension. ValueError if neither."""
    if isinstance(world, WorldMap):
        return world
    if not isinstance(world, str | Path):
        raise TypeError(f"world {world!r} is not a world's name, a path or a WorldMap")
    path = Path(world)
    try:
        return load_world(path if path.is_file() or path.suffix else bundled_world_path(str(path)))
    except BadInput as problem:
        raise ValueError(str(problem)) from None


def resolve_method(method: object) -> Method:
    """A method as given; a preset's name (`paper`, `default`); else the method file
    (TOML) at that path. None: ours, as `tvl run`'s default. ValueError naming what is
    wrong (TypeError for a value of the wrong kind)."""
    if method is None:
        return DEFAULT
    if not isinstance(method, Method | str | Path):
        raise TypeError(f"method {method!r} is not a Method, a preset's name or a method file")
    try:
        return resolve_named_method(method)
    except BadInput as problem:
        raise ValueError(str(problem)) from None


def resolve_robot(robot: RobotConfig | str | Path | None, method: Method) -> RobotConfig:
    """The robot's body (by default `tvl run`'s; a profile's name, `yamabico` or
    `turtlebot3`, or a robot file's path) with the method's sonar model, as `tvl run` gives a
    robot its method's sonar. ValueError naming what is wrong (TypeError for a value of the
    wrong kind)."""
    if robot is None:
        robot = ROBOT
    elif isinstance(robot, str | Path):
        try:
            robot = resolve_named_robot(robot, label="robot")
        except BadInput as problem:
            raise ValueError(str(problem)) from None
    elif not isinstance(robot, RobotConfig):
        raise TypeError(f"robot {robot!r} is not a RobotConfig, a robot's name or a robot file")
    return method.robot(robot)


def _pair(goal: object) -> tuple[float, float]:
    """(x, y) metres from a goal as given; ValueError or TypeError naming it."""
    if isinstance(goal, str | bytes) or not isinstance(goal, tuple | list | np.ndarray):
        raise TypeError(f"goal {goal!r} is not a pair (x, y) of metres")
    if len(goal) != 2 or not all(is_real(v) for v in goal):
        raise ValueError(f"goal {goal!r} is not a pair (x, y) of finite metres")
    return float(goal[0]), float(goal[1])


@dataclass(frozen=True, slots=True, eq=False)
class RobotTask:
    """What each robot is asked: its world, the robot, the task, what its actions stand for,
    and the method it is asked under (whose sonar model the robot carries and whose echo
    memory it perceives through)."""

    world: WorldMap
    robot: RobotConfig
    task: str  # one of TASKS
    goal_xy: tuple[float, float] | None  # metres; the `goal` task's only
    wall_distance_m: float | None  # body edge to the wall; the `wall` task's only
    actions: Actions
    method: Method
    # Odometry drifts, so its distance to the goal has no bound of its own: the world's
    # diagonal is as far as two points of the world can be, and the distance is capped there.
    far_m: float

    @classmethod
    def of(
        cls,
        world: str | Path | WorldMap,
        task: str,
        *,
        goal: object = None,
        wall_distance_m: object = None,
        speed_fraction: object = None,
        method: object = None,
        action_type: object = DISCRETE,
        robot: RobotConfig | str | Path | None = None,
    ) -> RobotTask:
        """The task from the environments' arguments (SonarRingEnv documents them); a
        ValueError (a TypeError for a value of the wrong kind) names what is wrong."""
        if task not in TASKS:
            raise ValueError(f"unknown task {task!r} (choose from {', '.join(TASKS)})")
        resolved = resolve_world(world)
        chosen = resolve_method(method)
        body = resolve_robot(robot, chosen)
        far_m = math.hypot(resolved.width_m, resolved.height_m)
        return cls(
            resolved,
            body,
            task,
            _goal(resolved, task, goal),
            _wall_distance(body, task, wall_distance_m),
            Actions.of(action_type, body, speed_fraction),
            chosen,
            far_m,
        )

    @property
    def memory(self) -> MemoryConfig:
        """The echo memory the robot perceives through: its method's."""
        return self.method.memory

    def observation_space(self) -> spaces.Box:
        sonar = self.robot.sonar
        low, high = [sonar.min_range_m] * sonar.count, [sonar.max_range_m] * sonar.count
        if self.goal_xy is not None:
            low, high = [*low, -math.pi, 0.0], [*high, math.pi, self.far_m]
        return spaces.Box(
            np.array(low, dtype=np.float32), np.array(high, dtype=np.float32), dtype=np.float32
        )

    def engine(self) -> StepEngine:
        """A step engine for one robot on the task, to be reset."""
        return StepEngine(self.world, self.robot, goal_xy=self.goal_xy, measure=self._measured)

    def engine_over(self, robot: BatchRobot) -> StepEngine:
        """A step engine for a batch's robot on the task, from where the robot is."""
        return StepEngine.over(robot, goal_xy=self.goal_xy, measure=self._measured)

    @property
    def _measured(self) -> bool:
        """Whether each step measures the true clearance: the wall task's reward needs it."""
        return self.task == WALL

    def goal_m(self, odometry: Pose) -> float:
        """Metres from the odometry's position to the goal."""
        assert self.goal_xy is not None
        return math.dist(odometry[:2], self.goal_xy)


def _goal(world: WorldMap, task: str, goal: object) -> tuple[float, float] | None:
    if task != GOAL:
        if goal is not None:
            raise ValueError("goal is for task 'goal' only")
        return None
    if goal is not None:
        x, y = _pair(goal)
        try:
            check_goal(world, x, y, where=f"goal {x:g},{y:g}")
        except BadInput as problem:
            raise ValueError(str(problem)) from None
        return (x, y)
    if not world.goals:
        raise ValueError(f"{world.name}: world has no goal; give one with goal=(x, y)")
    return world.goals[0]


def _wall_distance(robot: RobotConfig, task: str, distance_m: object) -> float | None:
    if task != WALL:
        if distance_m is not None:
            raise ValueError("wall_distance_m is for task 'wall' only")
        return None
    if distance_m is None:
        return WALL_DISTANCE_M
    # Farther than the ring ranges, the robot could not see the wall it is to keep.
    reach_m = robot.sonar.max_range_m
    if not is_real(distance_m) or not 0 < float(distance_m) < reach_m:  # type: ignore[arg-type]
        raise ValueError(f"wall_distance_m {distance_m!r} is outside (0, {reach_m:g}) m")
    return float(distance_m)  # type: ignore[arg-type]


def step_limit(steps: object) -> int | None:
    """An episode's step limit as given (None: none); TypeError or ValueError naming it."""
    return None if steps is None else positive_int(steps, "max_episode_steps")


def positive_int(value: object, name: str) -> int:
    """A count an argument gives, checked as Gymnasium users read it: TypeError for what is
    not an int, ValueError for one under 1, each naming the argument."""
    if not isinstance(value, int) or isinstance(value, bool):
        raise TypeError(f"{name} must be an int, actual type: {type(value)}")
    if value < 1:
        raise ValueError(f"{name} must be 1 or more, actual value: {value}")
    return value


def reset_option(options: object) -> bool:
    """Whether `reset(options=...)` asks to go on from where the last episode ended; a
    TypeError or ValueError naming the options if they are not `{"continue": bool}`."""
    if options is None:
        return False
    if not isinstance(options, dict):
        raise TypeError(f"reset options {options!r} are not a dict")
    unknown = sorted(str(key) for key in options if key != "continue")
    if unknown:
        raise ValueError(f"reset options {unknown} are unknown (the one option is 'continue')")
    going_on = options.get("continue", False)
    if not isinstance(going_on, bool | np.bool_):
        raise TypeError(f"reset option continue={going_on!r} is not True or False")
    return bool(going_on)


@dataclass(frozen=True, slots=True)
class RobotNow:
    """What the physics says of one robot after a step (or a reset)."""

    time_s: float
    pose: Pose  # the truth
    odometry: Pose
    bumped: bool
    clearance_m: float | None  # the truth, body edge to the nearest obstacle: the wall task's

    @classmethod
    def at(cls, engine: StepEngine) -> RobotNow:
        """Where the engine's robot is now (its clearance if the engine measures it)."""
        sim = engine.sim
        clearance_m = sim.clearance_m() if engine.measure else None
        return cls(sim.time_s, sim.pose, sim.odometry, sim.bumped, clearance_m)

    @classmethod
    def after(cls, outcome: StepOutcome) -> RobotNow:
        """Where a step left the robot, as the engine saw it."""
        seen, truth = outcome.observation, outcome.truth
        return cls(seen.time_s, truth.pose, seen.odometry, seen.bumped, truth.clearance_m)


class RobotEpisode:
    """One robot's episode of a task: its perception, rewards and end.

    Fed in order: `begin` with the engine once its robot is (re)set, then for each step
    `command` before the engine steps and `after` with the step's outcome. Every ring the
    episode takes it reads through the engine, which judges the next step by it.
    """

    def __init__(self, task: RobotTask) -> None:
        self.task = task
        self.ring = np.empty(task.robot.sonar.count)  # (16,) metres read after the last step
        self.last: tuple[object, float, tuple[str, ...]] | None = None  # action, reward, events
        self.last_command = STOP  # the last step's
        self.trail: list[tuple[float, float]] = []  # true positions this episode, metres
        self._perception = self._fresh_perception()
        self._odometry: Pose = task.world.start

    def _fresh_perception(self) -> Perception:
        """A memory that has heard nothing, clearing as the task's method says for its task."""
        task = self.task
        return Perception(task.memory, task.robot, seeking_goal=task.goal_xy is not None)

    def begin(
        self, engine: StepEngine, remember: bool = False
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """A new episode from where the engine's robot is: the observation and info.
        `remember`: a robot going on keeps what it heard; one starting afresh has heard
        nothing."""
        if not remember:
            self._perception = self._fresh_perception()
        now = RobotNow.at(engine)
        perceived = self._sense(engine.observation.ring_m, now)
        self.last = None
        self.trail = [now.pose[:2]]
        reached = self.task.goal_xy is not None and within_goal(now.odometry[:2], self.task.goal_xy)
        return self._observation(perceived, now), self._info(now, (), reached)

    def backoff(self, bumped: bool) -> list[Command]:
        """The commands that take the robot clear before it goes on from where its episode
        ended: after a bump driving forward, back BACKOFF_M along its path (as the robot
        learns in the paper); else none."""
        if bumped and drives_forward(self.last_command):
            return backoff_commands(self.last_command, self.task.robot, BACKOFF_M)
        return []

    def command(self, action: object) -> Command:
        """The command of an action, for the physics to hold for a step."""
        self.last_command = self.task.actions.command(action)
        return self.last_command

    def after(
        self, action: object, outcome: StepOutcome
    ) -> tuple[np.ndarray, float, bool, dict[str, Any]]:
        """After the engine stepped the robot: observation, reward, terminated and info. The
        outcome's events and goal are the engine's judge's."""
        before = self._odometry
        now = RobotNow.after(outcome)
        perceived = self._sense(outcome.observation.ring_m, now)
        reached = outcome.done
        reward = self._reward(before, now)
        terminated = now.bumped or (self.task.task == GOAL and reached)
        self.last = (action, reward, outcome.events)
        self.trail.append(now.pose[:2])
        info = self._info(now, outcome.events, reached)
        return self._observation(perceived, now), reward, terminated, info

    def _reward(self, before: Pose, now: RobotNow) -> float:
        """The task's reward of a step from odometry `before`: progress (metres forward, or
        nearer the goal), less a bump's penalty (core.reward); following a wall, less its
        error from the set distance too."""
        task = self.task
        if task.task == GOAL:
            return task.goal_m(before) - task.goal_m(now.odometry) - bump_penalty_m(now.bumped)
        reward = step_reward(before, now.odometry, now.bumped)
        if task.task == WALL:
            reward -= WALL_ERROR_WEIGHT * abs(self._wall_error_m(now))
        return reward

    def caption(self) -> str:
        """The last step's action and reward, as the renderings caption them."""
        if self.last is None:
            return "episode start"
        action, reward, _ = self.last
        return f"action {self.task.actions.name(action, self.last_command)}, reward {reward:+.3f}"

    def _wall_error_m(self, now: RobotNow) -> float:
        assert now.clearance_m is not None and self.task.wall_distance_m is not None
        return now.clearance_m - self.task.wall_distance_m

    def _sense(self, ring: np.ndarray, now: RobotNow) -> np.ndarray:
        """Take the ring read where the robot is; what perception makes of it."""
        self.ring = ring
        self._odometry = now.odometry
        return self._perception.sense(now.time_s, now.odometry, ring, self.task.goal_xy)

    def _observation(self, perceived: np.ndarray, now: RobotNow) -> np.ndarray:
        return observation_of(self.task, perceived, now.odometry)

    def _info(self, now: RobotNow, events: tuple[str, ...], reached: bool) -> dict[str, Any]:
        """The truth beside the observation: simulated time, true pose and odometry (x, y
        metres, heading radians, not wrapped), the bump sensor, and the contact events
        (core.contacts) the step began; seeking a goal, whether it is reached (also as
        `is_success`, the key RL libraries read); following a wall, the true clearance and
        its error from the set distance."""
        info: dict[str, Any] = {
            "time_s": now.time_s,
            "pose": np.array(now.pose),
            "odometry": np.array(now.odometry),
            "bumped": now.bumped,
            "events": events,
        }
        if self.task.task == GOAL:
            info["goal_reached"] = reached
            info["is_success"] = reached
        elif self.task.task == WALL:
            info["clearance_m"] = now.clearance_m
            info["wall_error_m"] = self._wall_error_m(now)
        return info


def observation_of(task: RobotTask, perceived: np.ndarray, odometry: Pose) -> np.ndarray:
    """What the robot observes: (16,) float32 metres, S0 forward, CCW (the echo memory's
    virtual ring with a memory); seeking a goal (18,): then its bearing (radians, left
    positive) and distance (metres), both by odometry."""
    if task.goal_xy is None:
        return perceived.astype(np.float32)
    bearing = goal_bearing(odometry, task.goal_xy)
    distance = min(task.goal_m(odometry), task.far_m)
    return np.array([*perceived, bearing, distance], dtype=np.float32)
