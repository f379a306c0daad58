"""The oracle velocities: the paper's decision rule, inside the method's reflexes, fed the true
velocity of every view's seven trajectories in place of a FAM's. A reference that reads the
map and the true pose, never a method: what the method could do with perfect perception, the
ceiling the generalization benchmark holds the FAMs to.

A trajectory's true velocity is the label its true collision point gives (sim.true_arcs),
by the method's deceleration and margin, the collision point where the body would come
within the sonar's blind zone (0.15 m) of an obstacle: nearer, the ring cannot tell it from
touching, and a run counts a near miss.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from tvl_cli.agent.drive import StepSink, drive_engine
from tvl_cli.agent.drive_tvl import behaving_policy
from tvl_cli.agent.engine import StepEngine
from tvl_cli.agent.policy import Pose
from tvl_cli.core.arcs import collision_clearance_m
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.core.labels import label_reach_m
from tvl_cli.core.method import Method
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.true_arcs import TrueArcs
from tvl_cli.sim.worldmap import WorldMap


class TrueVelocities:
    """Perceives like a FAM (`perceive`), from the true pose and the map."""

    def __init__(
        self,
        world: WorldMap,
        robot: RobotConfig,
        method: Method,
        true_pose: Callable[[], Pose] | None = None,
    ) -> None:
        """`true_pose` gives the pose `perceive` perceives from; a caller that names its own
        poses (`in_view`) needs none."""
        self._arcs = TrueArcs(world, robot, collision_clearance_m(robot))
        self._labels = (method.decel_mps2, method.margin_m)
        self._reach_m = label_reach_m(max(robot.v_max_mps), *self._labels)
        self._true_pose = true_pose
        count = robot.sonar.count
        self._views = np.arange(count) * (2 * math.pi / count)  # (16,) rad from the heading

    def perceive(self, ring_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(16, 7) m/s, view k facing sonar k, and the experience (all ones: known)."""
        velocities = self._velocities(self._pose_now(), self._views)
        return velocities, np.ones_like(velocities)

    def perceive_ahead(self, ring_m: np.ndarray) -> np.ndarray:
        """(7,) m/s: the true velocities of the view ahead alone."""
        return self.in_view(self._pose_now(), 0)

    def _pose_now(self) -> Pose:
        assert self._true_pose is not None, "perceiving needs the true pose"
        return self._true_pose()

    def in_view(self, pose: Pose, view: int) -> np.ndarray:
        """(7,) m/s: the true velocities of one view's trajectories (facing sonar `view`),
        from a pose of the caller's."""
        return self._velocities(pose, self._views[view : view + 1])[0]

    def _velocities(self, pose: Pose, views_rad: np.ndarray) -> np.ndarray:
        x, y, theta = pose
        found = self._arcs.view_distances_m(x, y, theta + views_rad, self._reach_m)
        return self._arcs.velocities_mps(found, *self._labels)


def behave_with_true_velocities(
    world: WorldMap,
    robot: RobotConfig,
    behaviour: str,
    *,
    minutes: float,
    seed: int,
    method: Method,
    threshold: float = DEFAULT_THRESHOLD,
    goal_xy: tuple[float, float] | None = None,
    on_step: StepSink | None = None,
) -> RunMetrics:
    """`agent.drive_tvl.behave`, with the true velocities in place of a FAM's: the method's
    reflexes, wall rule and perception of the ring (for the choice's other reads of it)."""
    engine = StepEngine(world, robot, goal_xy=goal_xy, measure=True)
    engine.reset(seed)
    velocities = TrueVelocities(world, robot, method, lambda: engine.sim.pose)
    policy = behaving_policy(robot, velocities, behaviour, method, threshold)
    return drive_engine(engine, policy, minutes, on_step=on_step)
