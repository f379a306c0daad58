"""The simulated robot: a disc driven by wheel commands in a pymunk world, with its sensors.

The wheels set the body's velocity at every physics sub-step; a contact removes only the part
of that velocity that would push into an obstacle, so the body stops at a wall or slides
along it but never enters it.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk

from tvl_cli.core.command import Command
from tvl_cli.core.config import RobotConfig
from tvl_cli.sim.sonar import SonarRing
from tvl_cli.sim.world import build_space, clearance_m, static_geometry
from tvl_cli.sim.worldmap import WorldMap

Pose = tuple[float, float, float]  # x, y metres; heading radians, CCW from +x, not wrapped


def _chord_ratio(half_turn: float) -> float:
    """Chord over arc length for an arc turning 2 * half_turn radians."""
    return math.sin(half_turn) / half_turn if half_turn else 1.0


class Simulator:
    """One robot in one world, stepped one control period at a time.

    `pose` is the truth; `odometry` is what the wheels report; `bumped` is true when the body
    touched an obstacle during the last control period (or, after `place`, touches one now).
    Headings are continuous (never wrapped), so turns add up: a full circle adds 2 pi.
    Sonar noise and odometry noise are drawn from the one generator given, in call order.
    """

    def __init__(self, world: WorldMap, robot: RobotConfig, rng: np.random.Generator) -> None:
        self.world = world
        self.robot = robot
        self.rng = rng
        self.geometry = static_geometry(world)
        self.sonar = SonarRing(robot.sonar, robot.radius_m)
        self._space, self._body = build_space(world, robot)
        self._contacts: list[tuple[float, float]] = []  # unit normals, body -> touched obstacle
        self._steps = 0
        self.bumped = False
        self.odometry: Pose = world.start
        self.place(*world.start)

    @property
    def pose(self) -> Pose:
        """The true pose."""
        return self._pose

    def _read_pose(self) -> None:
        # Read once per step: the loop, the sonar and the odometry all ask for the pose, and
        # pymunk's accessors cost more than the tuple.
        position = self._body.position
        self._pose = (position.x, position.y, self._body.angle)

    @property
    def time_s(self) -> float:
        """Simulated seconds since the simulator was made."""
        return self._steps * self.robot.control_period_s

    def place(self, x: float, y: float, theta: float) -> None:
        """Put the robot at rest at a pose; odometry starts again from it."""
        self._body.position = (x, y)
        self._body.angle = theta
        self._body.velocity = (0.0, 0.0)
        self._body.angular_velocity = 0.0
        self._space.reindex_shapes_for_body(self._body)
        self._read_pose()
        (disc,) = self._body.shapes
        # A placed body may already touch something; learn the contact normals before moving.
        self._contacts = [
            (info.contact_point_set.normal.x, info.contact_point_set.normal.y)
            for info in self._space.shape_query(disc)
        ]
        self.bumped = bool(self._contacts)
        self.odometry = (x, y, theta)

    def read_sonar(self) -> np.ndarray:
        """(16,) metres from each transducer, S0 forward, counter-clockwise."""
        return self.sonar.read(self.geometry, self.pose, self.rng)

    def clearance_m(self) -> float:
        """Metres from the body's edge to the nearest obstacle (0 when touching)."""
        x, y, _ = self.pose
        return clearance_m(self.geometry, x, y, self.robot.radius_m)

    def step(self, command: Command) -> None:
        """Hold the command for one control period, then update bump and odometry."""
        robot = self.robot
        linear = command.linear_mps
        angular = command.angular_radps
        if linear == 0.0:
            angular = max(-robot.spin_rate_radps, min(robot.spin_rate_radps, angular))
        dt = robot.control_period_s / robot.physics_substeps
        # Each sub-step moves along the chord of its arc, aimed at the arc's mid heading, so the
        # body lands exactly on the arc and never outruns the commanded speed.
        half_turn = 0.5 * angular * dt
        chord_speed = linear * _chord_ratio(half_turn)
        before = self.pose
        touched = False
        body, space_step = self._body, self._space.step  # looked up once: four sub-steps a step
        for _ in range(robot.physics_substeps):
            heading = body.angle + half_turn
            body.velocity = self._slide(
                chord_speed * math.cos(heading), chord_speed * math.sin(heading)
            )
            body.angular_velocity = angular
            space_step(dt)
            self._contacts = []
            body.each_arbiter(self._record_contact)
            touched = touched or bool(self._contacts)
        self.bumped = touched
        self._steps += 1
        self._read_pose()
        self._update_odometry(before, self.pose)

    def _record_contact(self, arbiter: pymunk.Arbiter) -> None:
        # The body's own shape comes first in its arbiters: the normal points to the obstacle.
        self._contacts.append((arbiter.normal.x, arbiter.normal.y))

    def _slide(self, vx: float, vy: float) -> tuple[float, float]:
        """The velocity without its parts that go into touched obstacles; zero in a wedge."""
        if not self._contacts:  # most sub-steps touch nothing
            return (vx, vy)
        for nx, ny in self._contacts:
            into = vx * nx + vy * ny
            if into > 0.0:
                vx, vy = vx - into * nx, vy - into * ny
        # Sliding off one contact may push into another: stuck in a corner, the wheels stall.
        if any(vx * nx + vy * ny > 1e-9 for nx, ny in self._contacts):
            return (0.0, 0.0)
        return (vx, vy)

    def _update_odometry(self, before: Pose, after: Pose) -> None:
        """Dead reckoning from the wheels' measured travel, each wheel with seeded noise.

        The wheels measure the body's real motion along its heading (they do not slip; sliding
        sideways along a wall is not seen). The track is the body's diameter.
        """
        turn = after[2] - before[2]
        mid = before[2] + 0.5 * turn
        chord = (after[0] - before[0]) * math.cos(mid) + (after[1] - before[1]) * math.sin(mid)
        travel = chord / _chord_ratio(0.5 * turn)
        track = 2.0 * self.robot.radius_m
        left = travel - 0.5 * track * turn
        right = travel + 0.5 * track * turn
        noise = self.robot.odometry_noise_fraction * self.rng.standard_normal(2)
        left += abs(left) * float(noise[0])
        right += abs(right) * float(noise[1])
        travel = 0.5 * (left + right)
        turn = (right - left) / track
        x, y, theta = self.odometry
        length = travel * _chord_ratio(0.5 * turn)
        self.odometry = (
            x + length * math.cos(theta + 0.5 * turn),
            y + length * math.sin(theta + 0.5 * turn),
            theta + turn,
        )
