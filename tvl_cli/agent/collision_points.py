"""Where exploratory learning places a collision point besides at a bump, by a method's
`near_m` (core.additions.ADDITIONS, "sonar collision points"): the paper's learner waits for
bumps alone (`near_m` 0)."""

from __future__ import annotations

import math

import numpy as np

from tvl_cli.core.robot_config import RobotConfig, sonars_within

# How much nearer than at the episode's start a sonar must read before `near_m` counts: well
# above the noise (about 1.2 cm close in), so a wall the robot runs beside but does not
# approach never ends an episode, and one it is leaving behind never does either.
NEAR_CLOSING_M = 0.05


class SonarCollisionPoints:
    """A sonar facing ahead of the body's middle (sideways ones included) reads within
    `near_m`, having closed in since the episode started."""

    def __init__(self, robot: RobotConfig, near_m: float) -> None:
        self.near_m = near_m
        self._ahead = np.array(sonars_within(math.pi / 2, robot.sonar.count))

    def reached(self, ring_m: np.ndarray, start_m: np.ndarray) -> bool:
        """Whether `ring_m` (16,) metres, against `start_m` at the episode's start, marks a
        collision point."""
        ahead = ring_m[self._ahead]
        closing = ahead < start_m[self._ahead] - NEAR_CLOSING_M
        return bool((closing & (ahead < self.near_m)).any())


def sonar_collision_points(robot: RobotConfig, near_m: float) -> SonarCollisionPoints | None:
    """The sonar's collision points of a method's `near_m`; None for bumps alone."""
    return SonarCollisionPoints(robot, near_m) if near_m > 0 else None
