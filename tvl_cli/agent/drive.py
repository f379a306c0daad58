"""The drive loop: learning's episodes, `tvl run` and every baseline drive through it.

Each control step the policy decides from what the robot knows, the engine (agent.engine)
steps the robot and judges the step, the metrics (core.metrics) take it in, and an optional
sink sees it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from tvl_cli.agent.engine import StepEngine
from tvl_cli.agent.policy import Decision, Policy
from tvl_cli.core.contacts import drives_forward
from tvl_cli.core.metrics import MetricsRecorder, RunMetrics
from tvl_cli.sim.robot import Pose, Simulator


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
    """Drive a simulator on from where its robot is (agent.engine judges the goal and the
    events; `measure=False` skips the true clearance, which learning needs none of)."""
    engine = StepEngine.over(
        sim, goal_xy=goal_xy, goal_by_odometry=goal_by_odometry, measure=measure
    )
    return drive_engine(engine, policy, minutes, on_step=on_step, stop=stop)


def drive_engine(
    engine: StepEngine,
    policy: Policy,
    minutes: float,
    *,
    on_step: StepSink | None = None,
    stop: Callable[[], bool] | None = None,
) -> RunMetrics:
    """Drive for `minutes` of simulated time, until the goal is reached, or until `stop()`."""
    dt = engine.robot.control_period_s
    obs = engine.observation
    metrics = MetricsRecorder(engine.sim.pose[:2])
    for _ in range(round(minutes * 60 / dt)):
        if stop is not None and stop():
            break
        decision = policy.decide(obs)
        step = engine.step(decision.command, trapped=decision.trapped)
        pose = step.truth.pose
        after = step.observation
        clearance_m = step.truth.clearance_m
        metrics.record(
            pose[:2],
            dt,
            0.0 if clearance_m is None else clearance_m,
            decision.following_wall,
            drives_forward(decision.command),
            step.events,
        )
        if on_step is not None:
            on_step(
                Step(
                    obs.time_s,
                    step.ring_m,
                    decision,
                    pose,
                    after.odometry,
                    after.bumped,
                    step.events,
                )
            )
        if step.done:
            metrics.goal_reached()
            break
        obs = after
    metrics.count(engine.finish())
    return metrics.result()
