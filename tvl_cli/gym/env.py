"""The simulator `tvl run` drives, as a Gymnasium environment: one step is one control period
of the step engine (agent.engine), the one `tvl run` steps.

The environment adds only what Gymnasium asks for: spaces, a reward and an end for each task
(gym.task), and rendering. Observations are the sonar ring (and, seeking a goal, the goal's
bearing and distance by odometry); actions are the trajectories at one speed, a spin either
way and a stop, or with `action_type="continuous"` any (speed, turn rate) within the robot's
limits. A bump ends an episode in every task.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, SupportsFloat

import gymnasium
import numpy as np

from tvl_cli.agent.engine import StepEngine
from tvl_cli.core.angles import goal_bearing
from tvl_cli.core.method import Method
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.gym.actions import (
    ACTION_NAMES,
    DISCRETE,
    ROBOT,
    SPIN_LEFT,
    SPIN_RIGHT,
    STOP_ACTION,
)
from tvl_cli.gym.task import (
    TASKS,
    RobotEpisode,
    RobotTask,
    reset_option,
    resolve_world,
    step_limit,
)
from tvl_cli.render.window import display_available
from tvl_cli.sim.worldmap import WorldMap

if TYPE_CHECKING:
    from tvl_cli.render.animate import RobotFrame
    from tvl_cli.render.window import FrameWindow

__all__ = [
    "ACTION_NAMES",
    "ROBOT",
    "SPIN_LEFT",
    "SPIN_RIGHT",
    "STOP_ACTION",
    "TASKS",
    "SonarRingEnv",
    "resolve_world",
]


HUMAN = "human"  # the render mode that opens a window


class SonarRingEnv(gymnasium.Env[np.ndarray, Any]):
    """The robot in a world, avoiding obstacles (`avoid`), seeking a goal (`goal`) or
    following a wall at a set distance (`wall`).

    The simulator draws all its noise from the environment's generator, seeded by
    `reset(seed=...)`: the same seed and actions give the same episode, and the same seed
    and commands as `tvl run` give its run, step for step.
    """

    # Gymnasium declares metadata on its Env as a mutable instance default; typed as it is.
    metadata: dict[str, Any] = {  # noqa: RUF012
        "render_modes": ["ansi", "rgb_array", HUMAN],
        "render_fps": 1 / ROBOT.control_period_s,
    }

    def __init__(
        self,
        world: str | Path | WorldMap = "square",
        task: str = "avoid",
        *,
        goal: tuple[float, float] | None = None,
        wall_distance_m: float | None = None,
        action_type: str = DISCRETE,
        speed_fraction: float | None = None,
        method: Method | str | Path | None = None,
        robot: RobotConfig | str | Path | None = None,
        render_mode: str | None = None,
        max_episode_steps: int | None = None,
    ) -> None:
        """`goal` (x, y metres) for the `goal` task, by default the world's first;
        `wall_distance_m` for the `wall` task, body edge to wall (default 0.4);
        `action_type` `discrete`, `continuous` or `normalised`; `speed_fraction` (discrete
        only, default 1) of each trajectory's maximum speed is what its action drives at;
        `method` (a Method, a preset's name `paper` or `default`, or a method file's path; by
        default ours, as `tvl run`'s) gives the robot its sonar model and makes the observed
        ring its echo memory's virtual ring, as a FAM trained by that method reads (the live
        ring for a method without one); `robot` (a RobotConfig, a profile's name such as
        `turtlebot3`, or a robot file; by default `tvl run`'s) is the body that carries that
        sonar; `max_episode_steps`, after which the environment truncates an episode itself
        (none by default: `gymnasium.make` adds its TimeLimit)."""
        self.metadata = {**self.metadata, "render_modes": _render_modes(render_mode)}
        self.max_episode_steps = step_limit(max_episode_steps)
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
        self.world = self.robot_task.world
        self.robot = self.robot_task.robot
        self.method = self.robot_task.method
        self.task = task
        self.goal_xy = self.robot_task.goal_xy
        self.render_mode = render_mode
        self.commands = self.robot_task.actions.commands
        self.action_space = self.robot_task.actions.space()
        self.observation_space = self.robot_task.observation_space()
        self._engine: StepEngine | None = None
        self._episode = RobotEpisode(self.robot_task)
        self._steps = 0  # of the episode under way
        self._ended: str | None = None  # "terminated" or "truncated" once it has ended
        self._frame: RobotFrame | None = None
        self._window: FrameWindow | None = None  # render_mode human's, opened when first drawn

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """A new episode from the world's start; with `options={"continue": True}`, from where
        the last one ended instead, backed off 0.15 m along its path if it ended in a bump
        (as the robot learns in the paper, and as the Q-learning baseline does)."""
        going_on = reset_option(options)
        if going_on and seed is not None:
            raise ValueError("a seed starts afresh: reset with continue takes none")
        if going_on and self._engine is None:
            raise ValueError("nothing to continue: reset() without it first")
        super().reset(seed=seed)
        if going_on:
            engine = self._running()
            for command in self._episode.backoff(engine.sim.bumped):
                engine.step(command)
            engine.go_on()
        else:
            engine = self._engine = self.robot_task.engine()
            engine.reset(self.np_random)
        began = self._episode.begin(engine, remember=going_on)
        self._steps, self._ended = 0, None
        if self.render_mode == HUMAN:
            self.render()
        return began

    def step(self, action: Any) -> tuple[np.ndarray, SupportsFloat, bool, bool, dict[str, Any]]:
        """One control period; ResetNeeded once the episode has ended (terminated, or
        truncated at the environment's own step limit) until `reset()`."""
        engine = self._running()
        if self._ended is not None:
            raise gymnasium.error.ResetNeeded(
                f"the episode has ended ({self._ended}): call reset() before step()"
            )
        outcome = engine.step(self._episode.command(action))
        obs, reward, terminated, info = self._episode.after(action, outcome)
        self._steps += 1
        limit = self.max_episode_steps
        truncated = limit is not None and self._steps >= limit
        if terminated or truncated:
            self._ended = "terminated" if terminated else "truncated"
        if self.render_mode == HUMAN:
            self.render()
        return obs, reward, terminated, truncated, info

    def render(self) -> str | np.ndarray | None:
        if self.render_mode == "ansi":
            return self._text(self._running())
        if self.render_mode == "rgb_array":
            return self._picture(self._running())
        if self.render_mode == HUMAN:
            self._show(self._picture(self._running()))
        return None

    def close(self) -> None:
        self._frame = None
        if self._window is not None:
            self._window.close()
            self._window = None

    def _show(self, frame: np.ndarray) -> None:
        """In a window, at the environment's own pace (render_fps), as Gymnasium's human
        mode is."""
        from tvl_cli.render.animate import WINDOW_DPI
        from tvl_cli.render.window import FrameWindow

        if self._window is None:
            self._window = FrameWindow(f"tvl: {self.world.name}", frame.shape[:2], WINDOW_DPI)
        self._window.show(frame)
        self._window.hold(1.0 / self.metadata["render_fps"])

    def _running(self) -> StepEngine:
        if self._engine is None:
            raise gymnasium.error.ResetNeeded("call reset() before step() or render()")
        return self._engine

    def _text(self, engine: StepEngine) -> str:
        sim = engine.sim
        x, y, heading = sim.pose
        last = self._episode.last
        events = " ".join(last[2]) if last else ""
        lines = [
            f"{sim.time_s:.1f} s  x {x:.2f} m  y {y:.2f} m  heading {math.degrees(heading):.0f}°"
            f"  {events}".rstrip(),
            self._episode.caption(),
            "sonar m  " + " ".join(f"{r:.2f}" for r in self._episode.ring),
        ]
        if self.goal_xy is not None:
            bearing = math.degrees(goal_bearing(sim.odometry, self.goal_xy))
            distance_m = self.robot_task.goal_m(sim.odometry)
            lines.append(f"goal {distance_m:.2f} m at {bearing:+.0f}° by odometry")
        return "\n".join(lines) + "\n"

    def _picture(self, engine: StepEngine) -> np.ndarray:
        # matplotlib only when a picture is wanted
        from tvl_cli.render.animate import DPI, WINDOW_DPI, RobotFrame

        sim = engine.sim
        if self._frame is None:
            world = (
                self.world if self.goal_xy is None else replace(self.world, goals=(self.goal_xy,))
            )
            dpi = WINDOW_DPI if self.render_mode == HUMAN else DPI
            self._frame = RobotFrame(world, self.robot, dpi)
        last = self._episode.last
        events = " ".join(last[2]) if last else ""
        return self._frame.draw(
            np.array(self._episode.trail),
            np.array(sim.pose),
            self._episode.ring,
            f"{sim.time_s:.1f} s  {events}",
            self._episode.caption(),
        )


def _render_modes(render_mode: str | None) -> list[str]:
    """The render modes this machine can give: a machine with no display shows no window
    (and Gymnasium's check_env renders each mode an environment lists). ValueError for a mode
    that is none of them."""
    modes = list(SonarRingEnv.metadata["render_modes"])
    if render_mode is not None and render_mode not in modes:
        raise ValueError(f"unknown render_mode {render_mode!r} (choose from {', '.join(modes)})")
    if display_available():
        return modes
    if render_mode == HUMAN:
        raise ValueError(
            "render_mode 'human' opens a window, and there is no display here ($DISPLAY is not "
            "set): use 'rgb_array' for the frames, or 'ansi'"
        )
    return [mode for mode in modes if mode != HUMAN]
