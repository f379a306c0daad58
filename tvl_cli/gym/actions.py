"""What the Gymnasium environment's actions stand for, and their checks.

Three kinds (`action_type`):
- `discrete`: the robot's trajectories at one speed, a spin either way and a stop;
- `continuous`: any (speed m/s, turn rate rad/s) within the robot's limits, in float64, so
  that any command a run gave can be given again exactly;
- `normalised`: the same as fractions of those limits, each within [-1, 1] in float32, the
  Box RL libraries ask for (Stable-Baselines3's checker warns of any other range or dtype).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np
from gymnasium import spaces

from tvl_cli.core.drive_command import STOP, Command
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT

DISCRETE, CONTINUOUS, NORMALISED = "discrete", "continuous", "normalised"
ACTION_TYPES = (DISCRETE, CONTINUOUS, NORMALISED)
ROBOT = DEFAULT_ROBOT  # the robot of `tvl run`, with the real (noisy, specular) sonar ring
# Discrete actions 0-6 are the trajectories T3L..T3R; then a spin on the spot each way, and a
# stop. (Numbered for the default robot; another robot's trajectories come first the same way.)
SPIN_LEFT = len(ROBOT.trajectories)
SPIN_RIGHT = SPIN_LEFT + 1
STOP_ACTION = SPIN_LEFT + 2


def action_names(robot: RobotConfig) -> tuple[str, ...]:
    """The discrete actions' names: the robot's trajectories, the spins and the stop."""
    return (*(t.name for t in robot.trajectories), "spin-left", "spin-right", "stop")


ACTION_NAMES = action_names(ROBOT)


def is_real(value: object) -> bool:
    """A finite real number, not a truth value."""
    return (
        isinstance(value, numbers.Real)
        and not isinstance(value, bool | np.bool_)
        and math.isfinite(float(value))
    )


@dataclass(frozen=True, slots=True, eq=False)
class Actions:
    """A robot's actions of one kind: their space, and the command each stands for."""

    action_type: str  # one of ACTION_TYPES
    robot: RobotConfig
    commands: tuple[Command, ...]  # by discrete action; empty for the others

    @classmethod
    def of(cls, action_type: object, robot: RobotConfig, speed_fraction: object) -> Actions:
        """A ValueError (a TypeError for a value of the wrong kind) names a bad argument."""
        if action_type not in ACTION_TYPES:
            raise ValueError(
                f"unknown action_type {action_type!r} (choose from {', '.join(ACTION_TYPES)})"
            )
        assert isinstance(action_type, str)
        if action_type != DISCRETE:
            if speed_fraction is not None:
                raise ValueError("speed_fraction is for discrete actions only")
            return cls(action_type, robot, ())
        fraction = 1.0 if speed_fraction is None else _speed_fraction(speed_fraction)
        commands = (
            *(Command.follow(t, fraction * t.v_max_mps) for t in robot.trajectories),
            Command.spin(robot.spin_rate_radps),
            Command.spin(-robot.spin_rate_radps),
            STOP,
        )
        return cls(action_type, robot, commands)

    @property
    def limits(self) -> tuple[float, float]:
        """The fastest the robot drives (m/s, forward or back: its fastest trajectory's
        speed) and turns (rad/s, its spin rate)."""
        return max(self.robot.v_max_mps), self.robot.spin_rate_radps

    def space(self) -> spaces.Discrete | spaces.Box:
        if self.action_type == DISCRETE:
            return spaces.Discrete(len(self.commands))
        if self.action_type == NORMALISED:
            return spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        v, w = self.limits
        return spaces.Box(np.array([-v, -w]), np.array([v, w]), dtype=np.float64)

    def command(self, action: object) -> Command:
        """The command an action stands for; ValueError (TypeError for one of the wrong
        kind) naming the action if the action space holds no such action."""
        if self.action_type == DISCRETE:
            return self.commands[self.index(action)]
        return self._continuous(action)

    def index(self, action: object) -> int:
        """A discrete action as an index of `commands`; ValueError or TypeError naming it."""
        n = len(self.commands)
        if isinstance(action, np.ndarray) and action.shape == ():
            action = action[()]
        if not isinstance(action, int | np.integer) or isinstance(action, bool | np.bool_):
            raise TypeError(f"action {action!r} is not an int of Discrete({n}) (0 to {n - 1})")
        if not 0 <= action < n:
            raise ValueError(f"action {action!r} is not in Discrete({n}) (0 to {n - 1})")
        return int(action)

    def name(self, action: object, command: Command) -> str:
        """An action as a caption shows it: a discrete one's name, else its command."""
        if self.action_type == DISCRETE:
            return action_names(self.robot)[self.index(action)]
        return f"{command.linear_mps:+.2f} m/s {command.angular_radps:+.2f} rad/s"

    def _continuous(self, action: object) -> Command:
        values = np.asarray(action)
        normalised = self.action_type == NORMALISED
        what = "speed, turn as fractions" if normalised else "speed m/s, turn rad/s"
        if values.dtype.kind not in "fiu":
            raise TypeError(f"action {action!r} is not ({what}) in numbers")
        if values.shape != (2,) or not np.isfinite(values).all():
            raise ValueError(f"action {action!r} is not a finite ({what})")
        space = self.space()
        assert isinstance(space, spaces.Box)
        # Judged in the action's own precision: a float32 agent's 0.6 m/s is 0.6000000238.
        precision = values.dtype if values.dtype.kind == "f" else np.float64
        if ((values < space.low.astype(precision)) | (values > space.high.astype(precision))).any():
            raise ValueError(f"action {action!r} is outside {self._limits_text()}")
        within = np.clip(values.astype(np.float64), space.low, space.high)
        if self.action_type == NORMALISED:
            within = within * np.array(self.limits)
        speed, turn = within.tolist()
        return Command(speed, turn)

    def _limits_text(self) -> str:
        v, w = self.limits
        if self.action_type == NORMALISED:
            return f"[-1, 1], as fractions of the top speed {v:g} m/s and the spin rate {w:g} rad/s"
        return f"the robot's limits: speed -{v:g} to {v:g} m/s, turn -{w:g} to {w:g} rad/s"


def _speed_fraction(value: object) -> float:
    if not is_real(value) or not 0 < float(value) <= 1:  # type: ignore[arg-type]
        raise ValueError(f"speed_fraction {value!r} is outside (0, 1]")
    return float(value)  # type: ignore[arg-type]
