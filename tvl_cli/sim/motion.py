"""How a wheel command moves one robot's body, how contacts limit it, and what odometry makes
of the motion: the per-robot rules that a lone Simulator and a RobotBatch both follow, so that
a robot in a batch moves exactly as it would alone.

The wheels set the body's velocity at every physics sub-step; a contact removes only the part
of that velocity that would push into an obstacle, so the body stops at a wall or slides
along it but never enters it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from tvl_cli.core.drive_command import Command
from tvl_cli.core.robot_config import RobotConfig

Pose = tuple[float, float, float]  # x, y metres; heading radians, CCW from +x, not wrapped
Contacts = list[tuple[float, float]]  # unit normals, body -> touched obstacle, pymunk's order


class SubstepMotion(NamedTuple):
    """What a command asks of each physics sub-step of its control period."""

    half_turn_rad: float  # half the sub-step's turn: the chord's heading from the body's
    chord_speed_mps: float  # along the chord, so that the body lands exactly on the arc
    angular_radps: float


def chord_ratio(half_turn: float) -> float:
    """Chord over arc length for an arc turning 2 * half_turn radians."""
    return math.sin(half_turn) / half_turn if half_turn else 1.0


def substep_motion(command: Command, robot: RobotConfig) -> SubstepMotion:
    """The command as sub-steps: a spin on the spot is held to the spin rate, and each
    sub-step moves along the chord of its arc so the body never outruns the commanded speed."""
    angular = command.angular_radps
    if command.linear_mps == 0.0:
        angular = max(-robot.spin_rate_radps, min(robot.spin_rate_radps, angular))
    half_turn = 0.5 * angular * (robot.control_period_s / robot.physics_substeps)
    return SubstepMotion(half_turn, command.linear_mps * chord_ratio(half_turn), angular)


def wheel_velocity(motion: SubstepMotion, angle: float, contacts: Contacts) -> tuple[float, float]:
    """The body's velocity (metres a second) for a sub-step starting at heading `angle`:
    along the chord, aimed at the arc's mid heading, less what goes into touched obstacles."""
    heading = angle + motion.half_turn_rad
    speed = motion.chord_speed_mps
    return slide(speed * math.cos(heading), speed * math.sin(heading), contacts)


def slide(vx: float, vy: float, contacts: Contacts) -> tuple[float, float]:
    """The velocity without its parts that go into touched obstacles; zero in a wedge."""
    if not contacts:  # most sub-steps touch nothing
        return (vx, vy)
    for nx, ny in contacts:
        into = vx * nx + vy * ny
        if into > 0.0:
            vx, vy = vx - into * nx, vy - into * ny
    # Sliding off one contact may push into another: stuck in a corner, the wheels stall.
    if any(vx * nx + vy * ny > 1e-9 for nx, ny in contacts):
        return (0.0, 0.0)
    return (vx, vy)


def odometry_after(
    odometry: Pose,
    before: Sequence[float],
    after: Sequence[float],
    robot: RobotConfig,
    rng: np.random.Generator,
) -> Pose:
    """Dead reckoning from the wheels' measured travel between two true poses, each wheel
    with seeded noise (two normal draws from rng). Poses are x, y metres and heading.

    The wheels measure the body's real motion along its heading (they do not slip; sliding
    sideways along a wall is not seen). The track is the body's diameter.
    """
    turn = after[2] - before[2]
    mid = before[2] + 0.5 * turn
    chord = (after[0] - before[0]) * math.cos(mid) + (after[1] - before[1]) * math.sin(mid)
    travel = chord / chord_ratio(0.5 * turn)
    track = 2.0 * robot.radius_m
    left = travel - 0.5 * track * turn
    right = travel + 0.5 * track * turn
    noise = robot.odometry_noise_fraction * rng.standard_normal(2)
    left += abs(left) * float(noise[0])
    right += abs(right) * float(noise[1])
    travel = 0.5 * (left + right)
    turn = (right - left) / track
    x, y, theta = odometry
    length = travel * chord_ratio(0.5 * turn)
    return (
        x + length * math.cos(theta + 0.5 * turn),
        y + length * math.sin(theta + 0.5 * turn),
        theta + turn,
    )
