"""N robots in one world, stepped together: one pymunk space for all their bodies and one
kernel call for all their sonar rays.

No robot sees or touches another: the ring is cast against the world's static geometry
alone, and the robots' discs share a shape group, which pymunk never collides. Each robot
follows a lone Simulator's rules (sim.motion, sim.bodies) with its own generator, so robot i
of a batch reads, moves, bumps and dead-reckons bit for bit as a Simulator given its
generator and its commands would (tests/sim/test_batch.py holds it to that).

One space gives the same results as a space per robot because nothing couples the bodies:
pymunk solves each contact between one robot and the static world, whose infinite mass no
impulse moves, and finds each body's contacts by querying the static shapes' own tree in the
same order whatever else the space holds.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pymunk
import pymunk.batch

from tvl_cli.core.drive_command import STOP, Command
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.bodies import ContactRecorder, place_body
from tvl_cli.sim.geometry import add_robot_body, clearances_m, static_geometry, static_space
from tvl_cli.sim.motion import Pose, odometry_after, substep_motion, wheel_velocity
from tvl_cli.sim.sonar import SonarRing
from tvl_cli.sim.worldmap import WorldMap

_POSE = pymunk.batch.BodyFields.POSITION | pymunk.batch.BodyFields.ANGLE
_ANGLE = pymunk.batch.BodyFields.ANGLE
_WHEELS = pymunk.batch.BodyFields.VELOCITY | pymunk.batch.BodyFields.ANGULAR_VELOCITY


class RobotBatch:
    """N independent robots in one world with one robot configuration, each with its own
    generator (rngs[i]), stepped one control period at a time, together.

    `poses` (N, 3) are the truth; `odometry` is what each robot's wheels report (a Pose
    each); `bumped` (N,) whether each body touched an obstacle during the last control
    period (or, after `place`, touches one now); `time_s` (N,) each robot's simulated
    seconds since it was made or restarted. Python's per-robot work in a sub-step is the
    wheel rule alone: pymunk's bodies are read and set all at once (pymunk.batch).
    """

    def __init__(
        self, world: WorldMap, robot: RobotConfig, rngs: Sequence[np.random.Generator]
    ) -> None:
        if not rngs:
            raise ValueError("a batch needs at least one robot")
        self.world = world
        self.robot = robot
        self.rngs = list(rngs)
        self.count = len(self.rngs)
        self.geometry = static_geometry(world)
        self.sonar = SonarRing(robot.sonar, robot.radius_m)
        self._space = static_space(world, robot)
        self._bodies = [add_robot_body(self._space, robot, world.start) for _ in self.rngs]
        self._contacts = ContactRecorder(self._space, self._bodies)
        self._read_buffer = pymunk.batch.Buffer()
        # (bodies, 3) velocity x, y (m/s) and angular velocity (rad/s) for every body in
        # pymunk's listing of the space's bodies, which also holds the static body that the
        # obstacles hang on: its row stays zero.
        self._wheels = np.zeros((self.count + 1, 3))
        self._wheel_buffer = pymunk.batch.Buffer()
        self._wheel_buffer.set_float_buf(self._wheels.reshape(-1))
        self._rows = self._find_rows()
        self._poses = np.empty((self.count, 3))  # (N, 3) x, y metres, heading rad
        self._clearances: np.ndarray | None = None  # (N,) metres at the poses; None: not yet
        # Rings read ahead of asking (read_ahead): robot -> (N,16) ring, and its generator's
        # state before the draw.
        self._ahead: dict[int, np.ndarray] = {}
        self._before_ahead: dict[int, Mapping[str, Any]] = {}
        self._steps = np.zeros(self.count, dtype=np.int64)  # control periods each has run
        self.bumped = np.zeros(self.count, dtype=bool)
        self.odometry: list[Pose] = [world.start] * self.count
        for i in range(self.count):
            self.place(i, *world.start)

    @property
    def poses(self) -> np.ndarray:
        """(N, 3) the true poses: x, y metres, heading radians (not wrapped)."""
        return self._poses.copy()

    @property
    def time_s(self) -> np.ndarray:
        """(N,) simulated seconds since each robot was made or restarted."""
        return self._steps * self.robot.control_period_s

    def place(self, i: int, x: float, y: float, theta: float) -> None:
        """Put robot i at rest at a pose; its odometry starts again from it."""
        touching = place_body(self._space, self._bodies[i], x, y, theta)
        self._contacts.set(i, touching)
        body = self._bodies[i]
        self._poses[i] = (body.position.x, body.position.y, body.angle)
        self._clearances = None
        self.bumped[i] = bool(touching)
        self.odometry[i] = (x, y, theta)

    def restart(self, i: int, rng: np.random.Generator) -> None:
        """Robot i begins again as a new Simulator with generator rng would: at the world's
        start, its clock at zero and nothing of its past left in the physics."""
        # A new body: the old one may still carry the solver's push out of a contact (pymunk
        # keeps it for the next step), and its disc pymunk's memory of past contacts.
        old = self._bodies[i]
        self._space.remove(old, *old.shapes)
        self._bodies[i] = add_robot_body(self._space, self.robot, self.world.start)
        self._contacts.adopt(i, self._bodies[i])
        self._rows = self._find_rows()  # pymunk moved its last body into the old one's row
        self.rngs[i] = rng
        self._steps[i] = 0
        self.place(i, *self.world.start)

    def read_sonar(self) -> np.ndarray:
        """(N, 16) metres from each robot's transducers, S0 forward, counter-clockwise."""
        return self.sonar.read_many(self.geometry, self._poses, self.rngs)

    def read_ahead(self, robots: Sequence[int]) -> None:
        """Read the rings of `robots` now, in one kernel call, for each to take when it
        reads its sonar (`alone(i).read_sonar()`) before the next step; `settle()` then gives
        each robot that did not its generator back as it was before the draw. So a robot
        that reads its ring on only some steps draws what a Simulator read only when asked
        draws, while those that read read together."""
        rows = list(robots)
        if not rows:
            return
        self._before_ahead = {i: self.rngs[i].bit_generator.state for i in rows}
        rings = self.sonar.read_many(self.geometry, self._poses[rows], [self.rngs[i] for i in rows])
        self._ahead = dict(zip(rows, rings, strict=True))

    def settle(self) -> None:
        """Every ring read ahead and not taken is undrawn: its robot's generator goes back."""
        for i in self._ahead:
            self.rngs[i].bit_generator.state = self._before_ahead[i]
        self._ahead, self._before_ahead = {}, {}

    def read_one(self, i: int) -> np.ndarray:
        """(16,) metres: robot i's ring, taken from what was read ahead if it was."""
        ring = self._ahead.pop(i, None)
        if ring is None:
            ring = self.sonar.read(self.geometry, self.robot_pose(i), self.rngs[i])
        return ring

    def robot_pose(self, i: int) -> Pose:
        """Robot i's true pose, as a Simulator gives it."""
        x, y, heading = self._poses[i].tolist()
        return (x, y, heading)

    def alone(self, i: int) -> BatchRobot:
        """Robot i, read as a lone Simulator is (for a StepEngine over it)."""
        return BatchRobot(self, i)

    def clearances_m(self) -> np.ndarray:
        """(N,) metres from each body's edge to the nearest obstacle (0 when touching)."""
        if self._clearances is None:
            self._clearances = clearances_m(self.geometry, self._poses[:, :2], self.robot.radius_m)
        return self._clearances.copy()

    def clearance_m(self, i: int) -> float:
        """Robot i's clearance, metres; all the robots' measured in one call a step."""
        if self._clearances is None:
            self._clearances = clearances_m(self.geometry, self._poses[:, :2], self.robot.radius_m)
        return float(self._clearances[i])

    def step(self, commands: Sequence[Command | None]) -> None:
        """Hold each robot's command for one control period, then update bumps and odometry.

        A robot whose command is None sits the step out, to be restarted or placed after it
        (as a vector environment's robot that is reset instead): its wheels hold still, and
        its clock, its odometry and its generator are left as they were.
        """
        if len(commands) != self.count:
            raise ValueError(f"{len(commands)} commands for {self.count} robots")
        robot = self.robot
        motions = [substep_motion(command or STOP, robot) for command in commands]
        dt = robot.control_period_s / robot.physics_substeps
        rows, wheels, contacts = self._rows, self._wheels, self._contacts
        wheels[rows, 2] = [motion.angular_radps for motion in motions]
        before = self._poses.tolist()
        angles = self._poses[:, 2].tolist()
        touched = np.zeros(self.count, dtype=bool)
        for substep in range(robot.physics_substeps):
            if substep:
                angles = self._read(_ANGLE)[rows].tolist()
            normals = contacts.normals
            wheels[rows, :2] = [
                wheel_velocity(motion, angle, normals[i])
                for i, (motion, angle) in enumerate(zip(motions, angles, strict=True))
            ]
            pymunk.batch.set_space_bodies(self._space, _WHEELS, self._wheel_buffer)
            contacts.clear()
            self._space.step(dt)
            touched[contacts.touching] = True
        self.bumped = touched
        self._steps += [command is not None for command in commands]
        self._poses = self._read(_POSE).reshape(-1, 3)[rows]
        self._clearances = None
        self.odometry = [
            odometry if command is None else odometry_after(odometry, start, end, robot, rng)
            for odometry, start, end, rng, command in zip(
                self.odometry, before, self._poses.tolist(), self.rngs, commands, strict=True
            )
        ]

    def _find_rows(self) -> slice | np.ndarray:
        """Each robot's row (N,) in pymunk's listing of the space's bodies."""
        listed = self._read(pymunk.batch.BodyFields.BODY_ID, dtype=np.uintp)
        row_of = {int(body_id): row for row, body_id in enumerate(listed)}
        rows = [row_of[body.id] for body in self._bodies]
        # pymunk lists bodies in the order they were added: a slice then picks them cheaper.
        return slice(0, self.count) if rows == list(range(self.count)) else np.array(rows)

    def _read(self, fields: pymunk.batch.BodyFields, dtype: type = np.float64) -> np.ndarray:
        """The fields of every body in the space, in pymunk's order, as a new array."""
        buffer = self._read_buffer
        buffer.clear()
        pymunk.batch.get_space_bodies(self._space, fields, buffer)
        raw = buffer.int_buf() if dtype is np.uintp else buffer.float_buf()
        return np.frombuffer(raw, dtype=dtype).copy()


class BatchRobot:
    """One robot of a RobotBatch, read as a lone Simulator is: its clock, true pose,
    odometry, bump sensor, sonar ring and clearance. The batch steps it, with the others."""

    def __init__(self, batch: RobotBatch, i: int) -> None:
        self.batch = batch
        self.index = i
        self.world = batch.world
        self.robot = batch.robot

    @property
    def time_s(self) -> float:
        return float(self.batch._steps[self.index]) * self.robot.control_period_s

    @property
    def pose(self) -> Pose:
        return self.batch.robot_pose(self.index)

    @property
    def odometry(self) -> Pose:
        return self.batch.odometry[self.index]

    @property
    def bumped(self) -> bool:
        return bool(self.batch.bumped[self.index])

    def read_sonar(self) -> np.ndarray:
        return self.batch.read_one(self.index)

    def clearance_m(self) -> float:
        return self.batch.clearance_m(self.index)

    def step(self, command: Command) -> None:
        raise RuntimeError("a batch's robots step together: RobotBatch.step")
