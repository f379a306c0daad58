"""Angles in radians."""

from __future__ import annotations

import math
from typing import TypeVar

import numpy as np

Angle = TypeVar("Angle", float, np.ndarray)


def wrap_rad(angle: Angle) -> Angle:
    """An angle (or an array of them) wrapped to [-pi, pi)."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


def goal_bearing(odometry: tuple[float, float, float], goal_xy: tuple[float, float]) -> float:
    """Goal direction relative to the heading, [-pi, pi), from odometry alone."""
    x, y, theta = odometry
    return wrap_rad(math.atan2(goal_xy[1] - y, goal_xy[0] - x) - theta)
