"""The Dynamic Window Approach with the world's true geometry: the upper reference, no learning.

It sees what no sonar can, the exact obstacles and its own true pose, so its collisions and
speed bound what a sensor-driven controller could hope for with the same robot.
"""

from __future__ import annotations

import numpy as np

from tvl_cli.agent.drive import StepSink, drive
from tvl_cli.agent.policy import Decision, Observation
from tvl_cli.agent.reflexes import wrap
from tvl_cli.baselines.dwa_window import (
    DwaParams,
    arc_lengths,
    arc_points,
    best_candidate,
    dynamic_window,
    free_distances,
    goal_headings,
    heading_scores,
    predicted_poses,
    ray_points,
    recovery_spin,
    wander_heading,
)
from tvl_cli.core.command import Command
from tvl_cli.core.config import RobotConfig
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.world import clearances_m
from tvl_cli.sim.worldmap import WorldMap

BEHAVIOURS = ("avoid", "goal")
DEFAULT_DWA = DwaParams()


class DwaPolicy:
    """Chooses (v, w) in the dynamic window around the last command it gave.

    It reads the simulator's true pose and geometry, not the observation: that is the point
    of this baseline. Advice from reflexes is ignored, but a reflex can still take over.
    """

    def __init__(
        self,
        sim: Simulator,
        params: DwaParams = DEFAULT_DWA,
        goal_xy: tuple[float, float] | None = None,
    ) -> None:
        self.sim = sim
        self.robot = sim.robot
        self.params = params
        self.goal_xy = goal_xy
        self._s_m = arc_lengths(params)  # (K,) metres
        rays = params.wander_rays
        # (D,) radians, 0 (straight on) included, every direction around the robot
        self._ray_offsets = (np.arange(rays) - rays // 2) * (2 * np.pi / rays)
        # The simulated wheels reach the commanded velocity at once, so the robot moves at
        # exactly what was last commanded: that is the window's centre.
        self.last = Command(0.0, 0.0)
        self._turn_side = 1  # keeps turning the way it last turned when it must spin free

    def _free(self, sim: Simulator, points: np.ndarray) -> np.ndarray:
        """(N,) free distances along paths sampled at (N, K, 2) points every arc step."""
        clearance = clearances_m(sim.geometry, points.reshape(-1, 2), self.robot.radius_m)
        return free_distances(
            clearance.reshape(points.shape[:2]), sim.clearance_m(), self._s_m, self.params
        )

    def _wander(self, sim: Simulator) -> float:
        free = self._free(sim, ray_points(sim.pose, self._ray_offsets, self._s_m))
        return wander_heading(sim.pose[2], self._ray_offsets, free, self.params, self._turn_side)

    def interrupt(self) -> None:
        # A reflex has driven the robot meanwhile: the window starts again from rest.
        self.last = Command(0.0, 0.0)

    def decide(self, obs: Observation) -> Decision:
        return Decision(self._command(self.sim))

    def _command(self, sim: Simulator) -> Command:
        pose = sim.pose
        period = self.robot.control_period_s
        candidates = dynamic_window(
            self.last.linear_mps, self.last.angular_radps, period, self.params
        )
        free = self._free(sim, arc_points(pose, candidates, self._s_m))  # (N,) metres
        predicted = predicted_poses(pose, candidates, period, self.params)  # (N, 3)
        if self.goal_xy is None:
            wanted: np.ndarray | float = self._wander(sim)
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
) -> RunMetrics:
    """One run from the world's start: `avoid` without a goal, goal seeking with one.

    The simulator's generator is seeded as `tvl run` seeds its own; the goal is judged on
    the true pose, by which the DWA localises.
    """
    sim = Simulator(world, robot, np.random.default_rng(seed))
    behaviour = "avoid" if goal_xy is None else "goal"
    policy = wrap(DwaPolicy(sim, params, goal_xy), reflexes, robot, behaviour)
    return drive(sim, policy, minutes, goal_xy=goal_xy, goal_by_odometry=False, on_step=on_step)
