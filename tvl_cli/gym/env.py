"""The simulator `tvl run` drives, as a Gymnasium environment: one step is one control period.

Observations are the sonar ring (and, seeking a goal, the goal's bearing and distance by
odometry); actions are the seven trajectories at one speed, a spin either way, and a stop.
A bump ends an episode in both tasks.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, SupportsFloat

import gymnasium
import numpy as np
from gymnasium import spaces

from tvl_cli.agent.drive import GOAL_RADIUS_M
from tvl_cli.agent.motions import BACKOFF_M, backoff_commands
from tvl_cli.agent.perception import Perception
from tvl_cli.agent.tvl import goal_bearing
from tvl_cli.baselines.qlearning import DEFAULT_Q, step_reward
from tvl_cli.core.behaviours import is_threshold
from tvl_cli.core.command import STOP, Command
from tvl_cli.core.config import RobotConfig
from tvl_cli.core.contacts import EventDetector, drives_forward, near_miss_sonars
from tvl_cli.core.errors import BadInput
from tvl_cli.core.memory import NO_MEMORY, MemoryConfig
from tvl_cli.sim.robot import Pose, Simulator
from tvl_cli.sim.worldgen import bundled_world_path
from tvl_cli.sim.worldmap import WorldMap, check_goal, load_world

if TYPE_CHECKING:
    from tvl_cli.render.animate import RobotFrame

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


class SonarRingEnv(gymnasium.Env[np.ndarray, np.int64]):
    """The robot in a world, avoiding obstacles (`avoid`) or seeking a goal (`goal`).

    The simulator draws all its noise from the environment's generator, seeded by
    `reset(seed=...)`: the same seed and actions give the same episode.
    """

    # Gymnasium declares metadata on its Env as a mutable instance default; typed as it is.
    metadata: dict[str, Any] = {  # noqa: RUF012
        "render_modes": ["ansi", "rgb_array"],
        "render_fps": 1 / ROBOT.control_period_s,
    }

    def __init__(
        self,
        world: str | Path | WorldMap = "square",
        task: str = "avoid",
        *,
        goal: tuple[float, float] | None = None,
        speed_fraction: float = 1.0,
        memory: MemoryConfig | str = NO_MEMORY,
        render_mode: str | None = None,
    ) -> None:
        """`goal` (x, y metres) for the `goal` task, by default the world's first;
        `speed_fraction` of each trajectory's maximum speed is what its action drives at;
        `memory` (a MemoryConfig, or the name of a kind with its default settings) makes the
        observed ring the echo memory's virtual ring, as a FAM trained through it reads."""
        if task not in TASKS:
            raise ValueError(f"unknown task {task!r} (choose from {', '.join(TASKS)})")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"unknown render_mode {render_mode!r} (choose from ansi, rgb_array)")
        if not is_threshold(speed_fraction):
            raise ValueError(f"speed_fraction {speed_fraction!r} is outside (0, 1]")
        self.world = resolve_world(world)
        try:
            self.memory = memory if isinstance(memory, MemoryConfig) else MemoryConfig(memory)
        except BadInput as problem:
            raise ValueError(str(problem)) from None
        self.task = task
        self.goal_xy = self._goal(goal)
        self.render_mode = render_mode
        self.commands: tuple[Command, ...] = (
            *(Command.follow(t, speed_fraction * t.v_max_mps) for t in ROBOT.trajectories),
            Command.spin(ROBOT.spin_rate_radps),
            Command.spin(-ROBOT.spin_rate_radps),
            STOP,
        )
        self.action_space = spaces.Discrete(len(self.commands))
        low, high = [ROBOT.sonar.min_range_m] * SONARS, [ROBOT.sonar.max_range_m] * SONARS
        # Odometry drifts, so its distance to the goal has no bound of its own: the world's
        # diagonal is as far as two points of the world can be, and the distance is capped there.
        self._far_m = math.hypot(self.world.width_m, self.world.height_m)
        if task == "goal":
            low, high = [*low, -math.pi, 0.0], [*high, math.pi, self._far_m]
        self.observation_space = spaces.Box(
            np.array(low, dtype=np.float32), np.array(high, dtype=np.float32), dtype=np.float32
        )
        self._sim: Simulator | None = None
        self._ring = np.empty(SONARS)  # (16,) metres read after the last step
        self._perceived = self._ring  # (16,) metres observed: the ring, or the virtual ring
        self._perception = Perception(self.memory, ROBOT)
        self._events = EventDetector(near_miss_sonars(SONARS), ROBOT.sonar.min_range_m)
        self._last: tuple[int, float, tuple[str, ...]] | None = None  # action, reward, events
        self._trail: list[tuple[float, float]] = []  # true positions this episode, metres
        self._frame: RobotFrame | None = None

    def _goal(self, goal: tuple[float, float] | None) -> tuple[float, float] | None:
        if self.task != "goal":
            if goal is not None:
                raise ValueError("goal is for task 'goal' only")
            return None
        if goal is not None:
            x, y = goal
            try:
                check_goal(self.world, x, y, where=f"goal {x:g},{y:g}")
            except BadInput as problem:
                raise ValueError(str(problem)) from None
            return (x, y)
        if not self.world.goals:
            raise ValueError(f"{self.world.name}: world has no goal; give one with goal=(x, y)")
        return self.world.goals[0]

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """A new episode from the world's start; with `options={"continue": True}`, from where
        the last one ended instead, backed off 0.15 m along its path if it ended in a bump
        (as the robot learns in the paper, and as the Q-learning baseline does)."""
        going_on = bool((options or {}).get("continue"))
        if going_on and seed is not None:
            raise ValueError("a seed starts afresh: reset with continue takes none")
        if going_on and self._sim is None:
            raise ValueError("nothing to continue: reset() without it first")
        super().reset(seed=seed)
        if going_on:
            sim = self._running()
            last = self.commands[self._last[0]] if self._last else STOP
            if sim.bumped and drives_forward(last):
                for command in backoff_commands(last, ROBOT, BACKOFF_M):
                    sim.step(command)
        else:
            sim = self._sim = Simulator(self.world, ROBOT, self.np_random)
            # A robot going on remembers what it heard; one starting afresh has heard nothing.
            self._perception = Perception(self.memory, ROBOT)
        self._events = EventDetector(near_miss_sonars(SONARS), ROBOT.sonar.min_range_m)
        self._sense(sim)
        self._last = None
        self._trail = [sim.pose[:2]]
        return self._observation(sim), self._info(sim, ())

    def step(
        self, action: np.int64 | int
    ) -> tuple[np.ndarray, SupportsFloat, bool, bool, dict[str, Any]]:
        sim = self._running()
        command = self.commands[int(action)]
        before = sim.odometry
        ring_before = self._ring
        sim.step(command)
        self._sense(sim)
        events = self._events.step(ring_before, command, sim.bumped, False)
        if self.goal_xy is None:
            reward = step_reward(before, sim.odometry, sim.bumped)
            terminated = sim.bumped
        else:
            progress_m = self._goal_m(before) - self._goal_m(sim.odometry)
            reward = progress_m - (DEFAULT_Q.collision_penalty if sim.bumped else 0.0)
            terminated = sim.bumped or self._goal_m(sim.odometry) <= GOAL_RADIUS_M
        self._last = (int(action), reward, events)
        self._trail.append(sim.pose[:2])
        return self._observation(sim), reward, terminated, False, self._info(sim, events)

    def render(self) -> str | np.ndarray | None:
        if self.render_mode == "ansi":
            return self._text(self._running())
        if self.render_mode == "rgb_array":
            return self._picture(self._running())
        return None

    def close(self) -> None:
        self._frame = None

    def _running(self) -> Simulator:
        if self._sim is None:
            raise gymnasium.error.ResetNeeded("call reset() before step() or render()")
        return self._sim

    def _sense(self, sim: Simulator) -> None:
        """Read the ring where the robot is, and what perception makes of it."""
        self._ring = sim.read_sonar()
        self._perceived = self._perception.sense(sim.time_s, sim.odometry, self._ring)

    def _goal_m(self, odometry: Pose) -> float:
        assert self.goal_xy is not None
        return math.dist(odometry[:2], self.goal_xy)

    def _observation(self, sim: Simulator) -> np.ndarray:
        """(16,) float32 metres, S0 forward, CCW (the echo memory's virtual ring with a
        memory); seeking a goal (18,): then its bearing (radians, left positive) and distance
        (metres), both by odometry."""
        if self.goal_xy is None:
            return self._perceived.astype(np.float32)
        bearing = goal_bearing(sim.odometry, self.goal_xy)
        distance = min(self._goal_m(sim.odometry), self._far_m)
        return np.array([*self._perceived, bearing, distance], dtype=np.float32)

    def _info(self, sim: Simulator, events: tuple[str, ...]) -> dict[str, Any]:
        """The truth beside the observation: simulated time, true pose and odometry (x, y
        metres, heading radians, not wrapped), the bump sensor, and the contact events
        (core.contacts) the step began."""
        info = {
            "time_s": sim.time_s,
            "pose": np.array(sim.pose),
            "odometry": np.array(sim.odometry),
            "bumped": sim.bumped,
            "events": events,
        }
        if self.goal_xy is not None:
            info["goal_reached"] = self._goal_m(sim.odometry) <= GOAL_RADIUS_M
        return info

    def _caption(self) -> str:
        if self._last is None:
            return "episode start"
        action, reward, _ = self._last
        return f"action {ACTION_NAMES[action]}, reward {reward:+.3f}"

    def _text(self, sim: Simulator) -> str:
        x, y, heading = sim.pose
        events = " ".join(self._last[2]) if self._last else ""
        lines = [
            f"{sim.time_s:.1f} s  x {x:.2f} m  y {y:.2f} m  heading {math.degrees(heading):.0f}°"
            f"  {events}".rstrip(),
            self._caption(),
            "sonar m  " + " ".join(f"{r:.2f}" for r in self._ring),
        ]
        if self.goal_xy is not None:
            bearing = math.degrees(goal_bearing(sim.odometry, self.goal_xy))
            lines.append(f"goal {self._goal_m(sim.odometry):.2f} m at {bearing:+.0f}° by odometry")
        return "\n".join(lines) + "\n"

    def _picture(self, sim: Simulator) -> np.ndarray:
        # matplotlib only when a picture is wanted
        from tvl_cli.render.animate import RobotFrame

        if self._frame is None:
            world = (
                self.world if self.goal_xy is None else replace(self.world, goals=(self.goal_xy,))
            )
            self._frame = RobotFrame(world, ROBOT)
        events = " ".join(self._last[2]) if self._last else ""
        return self._frame.draw(
            np.array(self._trail),
            np.array(sim.pose),
            self._ring,
            f"{sim.time_s:.1f} s  {events}",
            self._caption(),
        )
