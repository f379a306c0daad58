"""The Dynamic Window Approach, no learning, with one of two ways of knowing the obstacles:

- `map`: the world's true geometry and its own true pose. It sees what no sonar can, so its
  collisions and speed bound what a sensor-driven controller could hope for with the same
  robot: the speed reference;
- `ring`: what the sonar ring hears, placed by odometry: each echo a patch square to the beam
  that heard it (core.memory), the echoes of the last reading alone or, with an echo memory,
  those of its window. The same sensor as TVL's, so a reference for what a hand-made
  controller makes of it.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from tvl_cli.agent.drive import StepSink, drive
from tvl_cli.agent.perception import EchoMemory
from tvl_cli.agent.policy import Decision, Observation, Pose
from tvl_cli.agent.reflexes import wrap
from tvl_cli.baselines.dwa_window import (
    DwaParams,
    arc_lengths,
    arc_points,
    best_candidate,
    clearance_read_m,
    dynamic_window,
    goal_headings,
    heading_scores,
    lookahead_m,
    predicted_poses,
    ray_points,
    recovery_spin,
    wander_heading,
)
from tvl_cli.core.drive_command import Command
from tvl_cli.core.memory import NO_MEMORY, PATCHES, MemoryConfig
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.geometry import StaticGeometry, clearance_m, geometry_of
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap

BEHAVIOURS = ("avoid", "goal")
MAP, RING = "map", "ring"
SENSORS = (MAP, RING)
DEFAULT_DWA = DwaParams()
# How far from the body's edge a point on an arc is asked for obstacles while walking the
# arc (baselines.dwa_kernel): a point this clear vouches for the next 0.15 m of its arc, a
# fifth of the queries of asking every point, each still among few of the grid's cells.
WALK_M = 0.15


class Sensing(Protocol):
    def sense(self, obs: Observation) -> tuple[StaticGeometry, Pose]:
        """The obstacles and the robot's pose in the same frame, before a control step."""
        ...


class MapSensing:
    """The world's true geometry and the true pose: what no sonar gives."""

    def __init__(self, sim: Simulator) -> None:
        self._sim = sim

    def sense(self, obs: Observation) -> tuple[StaticGeometry, Pose]:
        return self._sim.geometry, self._sim.pose


class RingSensing:
    """The ring's echoes as patches in the odometry frame: the last reading's, or an echo
    memory's."""

    def __init__(self, robot: RobotConfig, memory: MemoryConfig, reach_m: float) -> None:
        self._reach_m = reach_m  # farther obstacles cannot change a choice
        if not memory.remembers:
            # The last reading alone, every echo of it, as the memory's patches.
            memory = MemoryConfig(
                PATCHES, window_s=robot.control_period_s, range_m=robot.sonar.max_range_m
            )
        self._memory = EchoMemory(memory, robot)
        self._dt_s = robot.control_period_s

    def sense(self, obs: Observation) -> tuple[StaticGeometry, Pose]:
        step = round(obs.time_s / self._dt_s)
        self._memory.remember(step, obs.odometry, obs.ring_m)
        surfaces = self._memory.surfaces(step, obs.odometry[:2], self._reach_m)
        return geometry_of(*surfaces), obs.odometry


class DwaPolicy:
    """Chooses (v, w) in the dynamic window around the last command it gave, avoiding the
    obstacles its sensing gives. Advice from reflexes is ignored, but a reflex can still take
    over."""

    def __init__(
        self,
        sensing: Sensing,
        robot: RobotConfig,
        params: DwaParams = DEFAULT_DWA,
        goal_xy: tuple[float, float] | None = None,
    ) -> None:
        self.sensing = sensing
        self.robot = robot
        self.params = params
        self.goal_xy = goal_xy
        self._s_m = arc_lengths(params)  # (K,) metres
        # Arc points are asked for obstacles only as near as the free distances can tell
        # apart, and only the points the walk along each arc cannot vouch for
        # (baselines.dwa_kernel): most of a run's time in a rooms world through the echo
        # memory's crowded patches went on asking them all (benchmarks/dwa_speed.py).
        self._read_m = clearance_read_m(self._s_m, params)
        rays = params.wander_rays
        # (D,) radians, 0 (straight on) included, every direction around the robot
        self._ray_offsets = (np.arange(rays) - rays // 2) * (2 * np.pi / rays)
        # The simulated wheels reach the commanded velocity at once, so the robot moves at
        # exactly what was last commanded: that is the window's centre.
        self.last = Command(0.0, 0.0)
        self._turn_side = 1  # keeps turning the way it last turned when it must spin free

    def _free(self, geometry: StaticGeometry, here: float, points: np.ndarray) -> np.ndarray:
        """(N,) free distances along paths sampled at (N, K, 2) points every arc step, from a
        pose `here` metres clear of the obstacles (baselines.dwa_kernel)."""
        from tvl_cli.baselines.dwa_kernel import walked_free_distances  # compiled

        radius = self.robot.radius_m
        # Too near is within the margin or, for a robot already that near, nearer than now.
        allowed = min(self.params.margin_m, here)
        free = np.empty(len(points))  # (N,) metres
        g = geometry
        walked_free_distances(
            np.ascontiguousarray(points, dtype=np.float64), self._s_m, allowed, here - allowed,
            g.seg_start, g.seg_delta, g.seg_len, g.grid.kernel_input, g.discs, g.rings, radius,
            self._read_m, WALK_M,
            free,
        )  # fmt: skip
        return free

    def _wander(self, geometry: StaticGeometry, pose: Pose, here: float) -> float:
        free = self._free(geometry, here, ray_points(pose, self._ray_offsets, self._s_m))
        return wander_heading(pose[2], self._ray_offsets, free, self.params, self._turn_side)

    def interrupt(self) -> None:
        # A reflex has driven the robot meanwhile: the window starts again from rest.
        self.last = Command(0.0, 0.0)

    def decide(self, obs: Observation) -> Decision:
        return Decision(self._command(*self.sensing.sense(obs)))

    def _command(self, geometry: StaticGeometry, pose: Pose) -> Command:
        period = self.robot.control_period_s
        candidates = dynamic_window(
            self.last.linear_mps, self.last.angular_radps, period, self.params
        )
        # The body's clearance where it stands, which every path's free distance starts from.
        here = clearance_m(geometry, pose[0], pose[1], self.robot.radius_m)
        free = self._free(geometry, here, arc_points(pose, candidates, self._s_m))  # (N,) m
        predicted = predicted_poses(pose, candidates, period, self.params)  # (N, 3)
        if self.goal_xy is None:
            wanted: np.ndarray | float = self._wander(geometry, pose, here)
        else:
            wanted = goal_headings(predicted, self.goal_xy)
        heading = heading_scores(predicted, wanted)
        pick = best_candidate(candidates, free, heading, self.params)
        if candidates.v_mps[pick] == 0.0 and self.last.linear_mps == 0.0:
            pick = recovery_spin(candidates, self._turn_side)
        if candidates.w_radps[pick] != 0.0:
            self._turn_side = 1 if candidates.w_radps[pick] > 0.0 else -1
        self.last = Command(float(candidates.v_mps[pick]), float(candidates.w_radps[pick]))
        return self.last


def run_dwa(
    world: WorldMap,
    robot: RobotConfig,
    minutes: float,
    seed: int,
    goal_xy: tuple[float, float] | None = None,
    params: DwaParams = DEFAULT_DWA,
    reflexes: tuple[str, ...] = (),
    on_step: StepSink | None = None,
    sensor: str = MAP,
    memory: MemoryConfig = NO_MEMORY,
) -> RunMetrics:
    """One run from the world's start: `avoid` without a goal, goal seeking with one.

    The simulator's generator is seeded as `tvl run` seeds its own. With the `map` the goal is
    judged on the true pose, by which that DWA localises; with the `ring`, by odometry, as TVL
    judges it, and the obstacles are the ring's echoes (and with `memory`, the remembered).
    """
    sim = Simulator(world, robot, np.random.default_rng(seed))
    behaviour = "avoid" if goal_xy is None else "goal"
    sensing: Sensing = (
        MapSensing(sim)
        if sensor == MAP
        else RingSensing(robot, memory, lookahead_m(params) + robot.radius_m)
    )
    policy = wrap(DwaPolicy(sensing, robot, params, goal_xy), reflexes, robot, behaviour)
    return drive(
        sim, policy, minutes, goal_xy=goal_xy, goal_by_odometry=sensor == RING, on_step=on_step
    )
