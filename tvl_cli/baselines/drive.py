"""The loop every baseline drives with: ask a policy for a command, step, measure as `tvl run`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Protocol

from tvl_cli.core.command import Command
from tvl_cli.core.metrics import MetricsRecorder, RunMetrics
from tvl_cli.run import GOAL_RADIUS_M
from tvl_cli.sim.robot import Pose, Simulator


class Policy(Protocol):
    def command(self, sim: Simulator) -> Command:
        """The command for the next control period, seeing the state the last one left."""
        ...


@dataclass(slots=True)
class Drive:
    """A driven run: its metrics and, step by step, what `render_path` draws."""

    metrics: RunMetrics
    poses: list[Pose] = field(default_factory=list)
    speeds_mps: list[float] = field(default_factory=list)
    bumped: list[bool] = field(default_factory=list)


def drive(
    sim: Simulator,
    policy: Policy,
    minutes: float,
    goal_xy: tuple[float, float] | None = None,
) -> Drive:
    """Drive for `minutes` of simulated time, or until the true pose is within the goal radius.

    The baselines are judged on the true pose: the DWA localises by knowing the world, and the
    Q-learner has no goal.
    """
    dt = sim.robot.control_period_s
    metrics = MetricsRecorder(sim.pose[:2])
    result = Drive(metrics.result())
    for _ in range(round(minutes * 60 / dt)):
        command = policy.command(sim)
        sim.step(command)
        pose = sim.pose
        metrics.record(pose[:2], dt, sim.bumped, sim.clearance_m(), following_wall=False)
        result.poses.append(pose)
        result.speeds_mps.append(command.linear_mps)
        result.bumped.append(sim.bumped)
        if goal_xy is not None and math.dist(pose[:2], goal_xy) <= GOAL_RADIUS_M:
            metrics.goal_reached()
            break
    result.metrics = metrics.result()
    return result
