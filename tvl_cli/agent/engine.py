"""The one step body: a robot in a world, stepped one control period at a time.

The robot is a lone Simulator, or one robot of a RobotBatch (sim.batch) stepped with the
others between the engine's `ready` and `stepped`, which are the step's two halves
(`step_together` steps an engine a robot so).

Every way of moving the simulated robot goes through it: the drive loop under learning, `tvl
run` and the baselines (agent.drive), and the Gymnasium environments (gym.env, and gym.vector
with an engine a robot of its batch). `reset(seed)`
puts the robot at the world's start and returns what it knows; `step(command)` holds the
command for a control period and returns what it knows then, the events the step began, the
truth beside them and whether the goal is reached.

What the robot knows is an Observation whose sonar ring is read on first use: a step where
nothing looks at the ring (a spin or a back-off under way) draws no sonar noise, so a drive's
random stream depends only on what reads the ring. A caller that reads it every step (an
environment returning it) draws the same noise as a drive whose policy does.

What the engine judges is a StepJudge's: the contact events of core.contacts, and the goal,
reached within GOAL_RADIUS_M.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from tvl_cli.agent.policy import LazyRing, Observation, Pose
from tvl_cli.core.behaviours import GOAL_RADIUS_M
from tvl_cli.core.contacts import EventDetector, near_miss_sonars
from tvl_cli.core.drive_command import Command
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.batch import BatchRobot, RobotBatch
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap


def within_goal(xy: tuple[float, float], goal_xy: tuple[float, float]) -> bool:
    """Whether a position (metres) is near enough the goal to have reached it."""
    return math.dist(xy, goal_xy) <= GOAL_RADIUS_M


class StepJudge:
    """What each step of one robot began, and whether it reached the goal.

    Fed in step order, after the physics: the ring read before the step (None when nobody
    read it), the command, the bump sensor, whether the policy found itself trapped, and the
    true pose and odometry after the step. The goal is judged by odometry, as a robot would;
    `goal_by_odometry=False` judges it on the true pose, for a baseline that localises by
    knowing the world.
    """

    def __init__(
        self,
        robot: RobotConfig,
        goal_xy: tuple[float, float] | None = None,
        goal_by_odometry: bool = True,
    ) -> None:
        self.goal_xy = goal_xy
        self.goal_by_odometry = goal_by_odometry
        self._events = EventDetector(near_miss_sonars(robot.sonar.count), robot.sonar.min_range_m)

    def needs_ring(self) -> bool:
        """Whether the next step's events need the ring read before it."""
        return self._events.needs_ring()

    def judge(
        self,
        ring_m: np.ndarray | None,
        command: Command,
        bumped: bool,
        trapped: bool,
        pose: Pose,
        odometry: Pose,
    ) -> tuple[tuple[str, ...], bool]:
        """The events the step began, and whether the robot is at its goal after it."""
        events = self._events.step(ring_m, command, bumped, trapped)
        if self.goal_xy is None:
            return events, False
        where = odometry if self.goal_by_odometry else pose
        return events, within_goal(where[:2], self.goal_xy)

    def finish(self) -> tuple[str, ...]:
        """Events still open when the drive ends (an approach that has not touched)."""
        return self._events.finish()


@dataclass(frozen=True, slots=True)
class Truth:
    """What the simulator knows of a step and the robot does not."""

    pose: Pose  # after the step
    clearance_m: float | None  # body edge to the nearest obstacle after it; None: not measured


@dataclass(frozen=True, slots=True)
class StepOutcome:
    """One control step as the engine saw it."""

    ring_m: np.ndarray | None  # (16,) metres read before the step; None if nobody read it
    observation: Observation  # what the robot knows after the step, for the next
    events: tuple[str, ...]  # core.contacts events the step began
    truth: Truth
    done: bool  # the goal is reached


class StepEngine:
    """One robot in one world: reset to the start, then stepped a command at a time.

    `goal_xy` is the goal every observation carries and the judge checks; `measure` asks
    for the true clearance after each step, which costs a geometry query.
    """

    def __init__(
        self,
        world: WorldMap,
        robot: RobotConfig,
        *,
        goal_xy: tuple[float, float] | None = None,
        goal_by_odometry: bool = True,
        measure: bool = False,
    ) -> None:
        self.world = world
        self.robot = robot
        self.goal_xy = goal_xy
        self.goal_by_odometry = goal_by_odometry
        self.measure = measure
        self._sim: Simulator | BatchRobot | None = None
        self._judge = StepJudge(robot, goal_xy, goal_by_odometry)
        self._observation: Observation | None = None

    @classmethod
    def over(
        cls,
        sim: Simulator | BatchRobot,
        *,
        goal_xy: tuple[float, float] | None = None,
        goal_by_odometry: bool = True,
        measure: bool = False,
    ) -> StepEngine:
        """An engine going on with a simulator already made, from where its robot is."""
        engine = cls(
            sim.world,
            sim.robot,
            goal_xy=goal_xy,
            goal_by_odometry=goal_by_odometry,
            measure=measure,
        )
        engine._sim = sim
        engine.go_on()
        return engine

    def reset(self, seed: int | np.random.Generator) -> Observation:
        """A new simulator with the robot at the world's start, drawing all its noise from
        `seed`'s generator (or the generator given); what the robot knows there."""
        rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        self._sim = Simulator(self.world, self.robot, rng)
        return self.go_on()

    def go_on(self) -> Observation:
        """Judging starts afresh from where the robot is, as after a reset (an episode that
        goes on where the last one ended); what the robot knows there."""
        self._judge = StepJudge(self.robot, self.goal_xy, self.goal_by_odometry)
        self._observation = self._observe(self.sim)
        return self._observation

    @property
    def sim(self) -> Simulator | BatchRobot:
        if self._sim is None:
            raise RuntimeError("reset the engine before stepping it")
        return self._sim

    @property
    def observation(self) -> Observation:
        """What the robot knows now."""
        if self._observation is None:
            raise RuntimeError("reset the engine before stepping it")
        return self._observation

    def step(self, command: Command, *, trapped: bool = False) -> StepOutcome:
        """Hold `command` for one control period; `trapped` says the policy found nothing to
        drive (an event the judge counts)."""
        self.ready()
        self.sim.step(command)
        return self.stepped(command, trapped=trapped)

    def ready(self) -> None:
        """Before a step's physics: the ring is read now if the judge will want it. (A
        RobotBatch steps its robots' physics together between this and `stepped`.)"""
        if self._judge.needs_ring():
            self.observation.ring.get()

    def stepped(self, command: Command, *, trapped: bool = False) -> StepOutcome:
        """After a step's physics: what the step began, the truth, and what the robot knows
        now."""
        sim = self.sim
        ring = self.observation.ring
        pose = sim.pose
        events, done = self._judge.judge(
            ring.value, command, sim.bumped, trapped, pose, sim.odometry
        )
        truth = Truth(pose, sim.clearance_m() if self.measure else None)
        self._observation = self._observe(sim)
        return StepOutcome(ring.value, self._observation, events, truth, done)

    def finish(self) -> tuple[str, ...]:
        """Events still open when the drive ends."""
        return self._judge.finish()

    def _observe(self, sim: Simulator | BatchRobot) -> Observation:
        return Observation(
            sim.time_s, LazyRing(sim.read_sonar), sim.odometry, sim.bumped, self.goal_xy
        )


def step_together(
    batch: RobotBatch,
    engines: Sequence[StepEngine],
    commands: Sequence[Command | None],
    *,
    trapped: Sequence[bool] | None = None,
) -> list[StepOutcome | None]:
    """One control period of every robot of `batch`, engine i (over `batch.alone(i)`) holding
    commands[i], trapped[i] saying its policy found nothing to drive (none trapped if not
    given): each engine's outcome, as its `step` would give it alone. A robot whose command
    is None sits the step out (RobotBatch.step), its engine untouched."""
    trapped = [False] * len(commands) if trapped is None else trapped
    for engine, command in zip(engines, commands, strict=True):
        if command is not None:
            engine.ready()
    # A ring read ahead (RobotBatch.read_ahead) that nobody took is undrawn before the robots
    # move, so each generator has drawn only the rings its robot read, as a lone one would.
    batch.settle()
    batch.step(commands)
    return [
        None if command is None else engine.stepped(command, trapped=stuck)
        for engine, command, stuck in zip(engines, commands, trapped, strict=True)
    ]


def hold_together(
    batch: RobotBatch, engines: Sequence[StepEngine], plans: Sequence[Sequence[Command]]
) -> None:
    """Engine i holds the commands of plans[i] in turn, a control period each, every robot
    stepped together (step_together); one whose plan is done, or empty, sits the rest out."""
    for k in range(max(map(len, plans), default=0)):
        step_together(batch, engines, [plan[k] if k < len(plan) else None for plan in plans])
