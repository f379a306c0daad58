"""The drive loop: learning's episodes, `tvl run` and every baseline drive through it.

Each control step the policy decides from what the robot knows, the engine (agent.engine)
steps the robot and judges the step, the metrics (core.metrics) take it in, and an optional
sink sees it. `drive_together` drives the robots of a RobotBatch so, a step at a time
together, each as `drive_engine` would drive it alone.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from tvl_cli.agent.engine import StepEngine, StepOutcome, step_together
from tvl_cli.agent.policy import Decision, Policy
from tvl_cli.core.contacts import drives_forward
from tvl_cli.core.metrics import MetricsRecorder, RunMetrics
from tvl_cli.sim.batch import RobotBatch
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
    under_way = Drive(engine, policy, minutes, on_step)
    while not under_way.over:
        if stop is not None and stop():
            break
        decision = under_way.decide()
        under_way.take(decision, engine.step(decision.command, trapped=decision.trapped))
    return under_way.result()


def drive_together(batch: RobotBatch, drives: Sequence[Drive]) -> list[RunMetrics]:
    """Drive robot i of `batch` by drives[i] (over an engine on `batch.alone(i)`), every
    robot a step together (agent.engine.step_together), until each drive is over. Each drive
    goes as drive_engine would drive it over a lone Simulator with robot i's generator: the
    rings of the robots likely to read theirs are read ahead together, a robot that did not
    read its ring gets its generator back, and one that reads it unforeseen reads it alone
    (RobotBatch); a robot whose drive is over sits the others' steps out."""
    if len(drives) != batch.count:
        raise ValueError(f"{len(drives)} drives for {batch.count} robots")
    engines = [d.engine for d in drives]
    # A policy reads its ring on some steps only (the TVL policy on about a third, in runs
    # of steps: between them it follows the trajectory it chose), so a robot that read its
    # ring on the last step is the one likely to read it on this one.
    readers = set(range(batch.count))
    while not all(d.over for d in drives):
        going = [i for i, d in enumerate(drives) if not d.over]
        batch.read_ahead([i for i in going if i in readers])
        decisions: list[Decision | None] = [None if d.over else d.decide() for d in drives]
        outcomes = step_together(
            batch,
            engines,
            [None if d is None else d.command for d in decisions],
            trapped=[d is not None and d.trapped for d in decisions],
        )
        readers = {i for i in going if drives[i].read_ring}
        for i in going:
            decision, outcome = decisions[i], outcomes[i]
            assert decision is not None and outcome is not None
            drives[i].take(decision, outcome)
    return [d.result() for d in drives]


class Drive:
    """One drive under way, a step at a time: the policy decides, the caller steps the
    engine, and the drive takes the outcome into the metrics and the sink."""

    def __init__(
        self, engine: StepEngine, policy: Policy, minutes: float, on_step: StepSink | None
    ) -> None:
        self.engine = engine
        self.policy = policy
        self.on_step = on_step
        self._dt = engine.robot.control_period_s
        self._left = round(minutes * 60 / self._dt)  # steps
        self._obs = engine.observation
        self._metrics = MetricsRecorder(engine.sim.pose[:2], engine.goal_xy is not None)

    @property
    def over(self) -> bool:
        """Its time is up, or its goal reached."""
        return self._left <= 0

    def decide(self) -> Decision:
        return self.policy.decide(self._obs)

    @property
    def read_ring(self) -> bool:
        """Whether the policy read the ring of the step it is deciding."""
        return self._obs.ring.value is not None

    def take(self, decision: Decision, step: StepOutcome) -> None:
        """A step's outcome, after the physics of `decision`."""
        pose = step.truth.pose
        after = step.observation
        clearance_m = step.truth.clearance_m
        self._metrics.record(
            pose[:2],
            self._dt,
            0.0 if clearance_m is None else clearance_m,
            decision.following_wall,
            drives_forward(decision.command),
            step.events,
        )
        if self.on_step is not None:
            self.on_step(
                Step(
                    self._obs.time_s,
                    step.ring_m,
                    decision,
                    pose,
                    after.odometry,
                    after.bumped,
                    step.events,
                )
            )
        self._left -= 1
        if step.done:
            self._metrics.goal_reached()
            self._left = 0
        self._obs = after

    def result(self) -> RunMetrics:
        """The drive's metrics, counting events still open."""
        self._metrics.count(self.engine.finish())
        return self._metrics.result()
