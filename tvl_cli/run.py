"""The behaviour loop: perceive with the FAM, choose a fast trajectory, drive it, measure."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from tvl_cli.core.angles import wrap_rad
from tvl_cli.core.behaviours import (
    DEFAULT_THRESHOLD,
    BlockedWay,
    Choice,
    Context,
    block_way,
    blocked_bearings,
    choose,
    nearest_side,
    trajectory_headings,
    wall_seen,
)
from tvl_cli.core.command import Command
from tvl_cli.core.config import RobotConfig, sonars_within
from tvl_cli.core.fam import Fam
from tvl_cli.core.metrics import MetricsRecorder, RunMetrics
from tvl_cli.learn import BACKOFF_M, backoff_commands, spin_commands
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap

GOAL_RADIUS_M = 0.3
# A sonar within this angle of straight ahead that reads inside its blind zone (at its minimum
# range) while the robot drives forward means an object the ring can no longer range is about
# to meet the body: the robot backs off as after a bump, without touching. (Learning places a
# collision point where a sonar ahead enters the blind zone for the same reason; see
# `LearnParams.near_m`.) Sideways sonars do not count: a wall alongside, as in a narrow
# passage, is passed, not met.
NEAR_MISS_WITHIN_RAD = math.pi / 4
# How long a way that met an obstacle stays out of the choice (BlockedWay), once backed off:
# time to drive clear of the spot, short enough to try that way again later.
BLOCKED_S = 2.0
# Trapped: turn slowly on the spot so the ring sees new directions.
TRAPPED_SPIN_RADPS = 0.3


@dataclass(frozen=True, slots=True)
class RunParams:
    behaviour: str
    threshold: float = DEFAULT_THRESHOLD
    minutes: float = 5.0
    goal_xy: tuple[float, float] | None = None
    near_miss_backoff: bool = True  # back off when an object enters the blind zone ahead


@dataclass(slots=True)
class StepRecord:
    """One control step of a run trace."""

    pose: tuple[float, float, float]
    odometry: tuple[float, float, float]
    ring_m: np.ndarray  # (16,) metres
    velocities: np.ndarray  # (7,) perceived m/s facing forward
    trajectory: int  # -1 while spinning, reversing or trapped
    speed_mps: float
    bumped: bool


@dataclass(slots=True)
class RunResult:
    metrics: RunMetrics
    path: list[tuple[float, float, float]] = field(default_factory=list)
    # Back-offs made before any contact, when an object entered the blind zone ahead.
    near_misses: int = 0


TraceFn = Callable[[StepRecord], None]


def goal_bearing(odometry: tuple[float, float, float], goal_xy: tuple[float, float]) -> float:
    """Goal direction relative to the heading, [-pi, pi), from odometry alone."""
    x, y, theta = odometry
    return wrap_rad(math.atan2(goal_xy[1] - y, goal_xy[0] - x) - theta)


class Runner:
    def __init__(
        self,
        world: WorldMap,
        robot: RobotConfig,
        fam: Fam,
        params: RunParams,
        seed: int,
    ) -> None:
        self.robot = robot
        self.fam = fam
        self.params = params
        self.sim = Simulator(world, robot, np.random.default_rng(seed))
        self._v_max = np.array(robot.v_max_mps)
        curvatures = np.array([t.curvature_per_m for t in robot.trajectories])
        self._headings = trajectory_headings(curvatures, robot.sonar.count)
        # Where each trajectory sets off: its heading over the back-off distance, the stretch
        # in which an obstacle just met lies.
        self._starts = trajectory_headings(curvatures, robot.sonar.count, BACKOFF_M)
        self._queue: list[tuple[Command, int]] = []  # commands already decided
        self._last_turn = 1
        self._wall_side = 0
        self._trapped = False
        self._blocked: list[BlockedWay] = []
        self._front = np.array(sonars_within(NEAR_MISS_WITHIN_RAD, robot.sonar.count))
        self._forward: Command | None = None  # the last command, if it followed a trajectory

    def _context(self, ring_m: np.ndarray) -> Context:
        behaviour = self.params.behaviour
        if behaviour == "wall" and self._wall_side == 0:
            self._wall_side = nearest_side(ring_m)
        elif behaviour.startswith("wall-") and self._wall_side == 0:
            side = 1 if behaviour == "wall-left" else -1
            self._wall_side = side if wall_seen(ring_m, side) else 0
            if self._wall_side == 0:
                # Until its wall is found, turn away from that side at a tie, so that the
                # first wall met ahead is left on the side to follow (not kept on the other).
                self._last_turn = -side
        bearing = (
            goal_bearing(self.sim.odometry, self.params.goal_xy) if self.params.goal_xy else 0.0
        )
        blocked = blocked_bearings(self._blocked, self.sim.odometry[2], self.sim.time_s)
        return Context(ring_m, self._last_turn, bearing, self._wall_side, blocked)

    def _plan(self, choice: Choice) -> None:
        self._queue = [(c, -1) for c in spin_commands(choice.rotation, self.robot)]
        traj = self.robot.trajectories[choice.trajectory]
        self._queue.append((Command.follow(traj, choice.speed_mps), choice.trajectory))
        # The side the robot turns to, spin and arc together, is the side a tie keeps next.
        side = int(
            np.sign(self._headings[choice.rotation % len(self._headings), choice.trajectory])
        )
        if side:
            self._last_turn = side

    @property
    def blocked_ways(self) -> tuple[BlockedWay, ...]:
        """The ways that met obstacles, kept out of the choices until their times."""
        return tuple(self._blocked)

    def _back_off(self, forward: Command) -> None:
        """Reverse along the arc that met (or nearly met) an obstacle, and keep the way it
        was driving out of the choices until BLOCKED_S after the back-off."""
        reverse = backoff_commands(forward, self.robot, BACKOFF_M)
        self._queue = [(c, -1) for c in reverse]
        now = self.sim.time_s
        clear_s = now + len(reverse) * self.robot.control_period_s + BLOCKED_S
        self._blocked = block_way(self._blocked, BlockedWay(self.sim.odometry[2], clear_s), now)

    def _blind_ahead(self, ring_m: np.ndarray) -> bool:
        """A front sonar reads its minimum range: something is inside its blind zone."""
        return bool((ring_m[self._front] <= self.robot.sonar.min_range_m).any())

    def run(self, trace: TraceFn | None = None) -> RunResult:
        metrics = MetricsRecorder(self.sim.pose[:2])
        result = RunResult(metrics.result())
        dt = self.robot.control_period_s
        steps = round(self.params.minutes * 60 / dt)
        for _ in range(steps):
            ring_m = self.sim.read_sonar()
            forward = self._forward
            if forward is not None and self.params.near_miss_backoff and self._blind_ahead(ring_m):
                self._back_off(forward)
                result.near_misses += 1
            velocities, _ = self.fam.perceive(ring_m)
            ctx = self._context(ring_m)
            if not self._queue:
                choice = choose(
                    velocities,
                    self._v_max,
                    self._headings,
                    self._starts,
                    self.params.behaviour,
                    self.params.threshold,
                    ctx,
                )
                if choice is None:
                    if not self._trapped:
                        metrics.trapped()
                    self._trapped = True
                    self._queue = [(Command.spin(TRAPPED_SPIN_RADPS * self._last_turn), -1)]
                else:
                    self._trapped = False
                    self._plan(choice)
            command, trajectory = self._queue.pop(0)
            self.sim.step(command)
            # Only a planned trajectory drives forward; spins and back-offs never do.
            self._forward = command if trajectory >= 0 else None
            if self.sim.bumped and self._forward is not None:
                # Back off along the arc that met the obstacle (a spin or a back-off cannot
                # have driven into it), as learning does.
                self._back_off(self._forward)
                self._forward = None
            pose = self.sim.pose
            metrics.record(
                pose[:2], dt, self.sim.bumped, self.sim.clearance_m(), self._wall_side != 0
            )
            result.path.append(pose)
            if trace is not None:
                trace(
                    StepRecord(
                        pose,
                        self.sim.odometry,
                        ring_m,
                        velocities[0],
                        trajectory,
                        command.linear_mps,
                        self.sim.bumped,
                    )
                )
            goal = self.params.goal_xy
            if goal is not None and math.dist(self.sim.odometry[:2], goal) <= GOAL_RADIUS_M:
                metrics.goal_reached()
                break
        result.metrics = metrics.result()
        return result
