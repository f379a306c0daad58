"""Motions made of several control steps: spinning to face a sonar, reversing along an arc."""

from __future__ import annotations

import math

from tvl_cli.core.drive_command import Command
from tvl_cli.core.robot_config import RobotConfig


def backoff_commands(forward: Command, robot: RobotConfig, distance_m: float) -> list[Command]:
    """Commands that drive back along the arc `forward` was following, for distance_m."""
    step_m = forward.linear_mps * robot.control_period_s
    steps = math.ceil(distance_m / step_m - 1e-9)
    return [Command(-forward.linear_mps, -forward.angular_radps)] * steps


def spin_commands(sonar_offset: int, robot: RobotConfig) -> list[Command]:
    """Commands that turn the robot in place to face sonar `sonar_offset` (CCW positive),
    the shorter way round, at its spin rate, ending exactly on the angle."""
    count = robot.sonar.count
    offset = (sonar_offset + count // 2) % count - count // 2  # -8..7
    angle = offset * 2 * math.pi / count
    per_step = robot.spin_rate_radps * robot.control_period_s
    steps = math.ceil(abs(angle) / per_step - 1e-9)
    if steps == 0:
        return []
    return [Command.spin(angle / (steps * robot.control_period_s))] * steps
