"""The simulated robot: a disc driven by wheel commands in a pymunk world, with its sensors.

How a command moves the body, slides it along walls and what odometry reports are the
per-robot rules of sim.motion, which a RobotBatch (sim.batch) follows too.
"""

from __future__ import annotations

import numpy as np

from tvl_cli.core.drive_command import Command
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.bodies import ContactRecorder, place_body
from tvl_cli.sim.geometry import build_space, clearance_m, static_geometry
from tvl_cli.sim.motion import Pose, odometry_after, substep_motion, wheel_velocity
from tvl_cli.sim.sonar import SonarRing
from tvl_cli.sim.worldmap import WorldMap

__all__ = ["Pose", "Simulator"]


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
        self._contacts = ContactRecorder(self._space, [self._body])
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
        # A placed body may already touch something; learn the contact normals before moving.
        touching = place_body(self._space, self._body, x, y, theta)
        self._contacts.set(0, touching)
        self._read_pose()
        self.bumped = bool(touching)
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
        motion = substep_motion(command, robot)
        dt = robot.control_period_s / robot.physics_substeps
        before = self.pose
        touched = False
        body, space_step = self._body, self._space.step  # looked up once: four sub-steps a step
        contacts = self._contacts
        for _ in range(robot.physics_substeps):
            body.velocity = wheel_velocity(motion, body.angle, contacts.normals[0])
            body.angular_velocity = motion.angular_radps
            contacts.clear()
            space_step(dt)
            touched = touched or bool(contacts.touching)
        self.bumped = touched
        self._steps += 1
        self._read_pose()
        self.odometry = odometry_after(self.odometry, before, self.pose, robot, self.rng)
