"""The one step loop: learning's episodes, `tvl run` and every baseline drive through it.

Each control step: observe, let the policy decide, step the simulator, detect the events the
step began (core.contacts), measure (core.metrics), and hand the step to an optional sink.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from tvl_cli.agent.policy import Decision, LazyRing, Observation, Policy
from tvl_cli.core.contacts import EventDetector, drives_forward, near_miss_sonars
from tvl_cli.core.metrics import MetricsRecorder, RunMetrics
from tvl_cli.sim.robot import Pose, Simulator

GOAL_RADIUS_M = 0.3  # a goal counts as reached this near


@dataclass(frozen=True, slots=True)
class Step:
    """One control step as the loop saw it."""

    time_s: float  # simulated time before the step
    ring_m: np.ndarray | None  # (16,) metres read before the step; None if nobody read it
    decision: Decision
    pose: Pose  # true pose after the step
    odometry: Pose  # after the step
    bumped: bool  # bump sensor after the step
    events: tuple[str, ...]  # core.contacts events the step began


StepSink = Callable[[Step], None]


def drive(
    sim: Simulator,
    policy: Policy,
    minutes: float,
    *,
    goal_xy: tuple[float, float] | None = None,
    goal_by_odometry: bool = True,
    on_step: StepSink | None = None,
    stop: Callable[[], bool] | None = None,
    measure: bool = True,
) -> RunMetrics:
    """Drive for `minutes` of simulated time, until the goal is reached, or until `stop()`.

    The goal is judged by odometry, as a robot would (TVL); `goal_by_odometry=False` judges
    it on the true pose, for a baseline that localises by knowing the world. `measure=False`
    skips the true clearance, which costs a geometry query a step (learning needs none).
    """
    robot = sim.robot
    dt = robot.control_period_s
    metrics = MetricsRecorder(sim.pose[:2])
    detector = EventDetector(near_miss_sonars(robot.sonar.count), robot.sonar.min_range_m)
    for _ in range(round(minutes * 60 / dt)):
        if stop is not None and stop():
            break
        time_s = sim.time_s
        ring = LazyRing(sim.read_sonar)
        if detector.needs_ring():
            ring.get()
        obs = Observation(time_s, ring, sim.odometry, sim.bumped, goal_xy)
        decision = policy.decide(obs)
        sim.step(decision.command)
        events = detector.step(ring.value, decision.command, sim.bumped, decision.trapped)
        pose = sim.pose
        metrics.record(
            pose[:2],
            dt,
            sim.clearance_m() if measure else 0.0,
            decision.following_wall,
            drives_forward(decision.command),
            events,
        )
        if on_step is not None:
            on_step(Step(time_s, ring.value, decision, pose, sim.odometry, sim.bumped, events))
        if goal_xy is not None:
            where = sim.odometry if goal_by_odometry else pose
            if math.dist(where[:2], goal_xy) <= GOAL_RADIUS_M:
                metrics.goal_reached()
                break
    metrics.count(detector.finish())
    return metrics.result()
