"""A behaviour run: the paper's TVL policy inside a method's reflexes, driven from the
world's start for some simulated minutes; or many such runs in one world, driven together."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from tvl_cli.agent.drive import Drive, StepSink, drive_engine, drive_together
from tvl_cli.agent.engine import StepEngine
from tvl_cli.agent.perception import Perception
from tvl_cli.agent.policy import Policy
from tvl_cli.agent.reflexes import wrap
from tvl_cli.agent.tvl import TvlPolicy, VelocityPerception
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.core.fam import Fam
from tvl_cli.core.method import Method
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.batch import RobotBatch
from tvl_cli.sim.worldmap import WorldMap


def behave(
    world: WorldMap,
    robot: RobotConfig,
    fam: Fam,
    behaviour: str,
    *,
    minutes: float,
    seed: int,
    method: Method,
    threshold: float = DEFAULT_THRESHOLD,
    goal_xy: tuple[float, float] | None = None,
    on_step: StepSink | None = None,
    stop: Callable[[], bool] | None = None,
) -> RunMetrics:
    """Perform `behaviour` with a FAM by `method`'s choices of behaving: perceiving through
    its echo memory, finding walls by its wall rule, inside its reflexes, until its time is
    up, its goal reached or `stop()`. The simulator's generator is seeded with `seed`."""
    engine = StepEngine(world, robot, goal_xy=goal_xy, measure=True)
    engine.reset(seed)
    policy = behaving_policy(robot, fam, behaviour, method, threshold)
    return drive_engine(engine, policy, minutes, on_step=on_step, stop=stop)


@dataclass(frozen=True, slots=True)
class BehaviourRun:
    """One run's own choices, of many in one world (behave_together)."""

    fam: Fam
    behaviour: str
    seed: int
    goal_xy: tuple[float, float] | None = None
    on_step: StepSink | None = None
    threshold: float | None = None  # None: the threshold of the runs driven together


def behave_together(
    world: WorldMap,
    robot: RobotConfig,
    runs: Sequence[BehaviourRun],
    *,
    minutes: float,
    method: Method,
    threshold: float = DEFAULT_THRESHOLD,
) -> list[RunMetrics]:
    """Each run's metrics, as `behave` gives them run by run, from the runs' robots stepped
    together in one RobotBatch: one physics space, and their rings read in one kernel call a
    step. Each run is made at its own threshold, if it has one."""
    batch = RobotBatch(world, robot, [np.random.default_rng(run.seed) for run in runs])
    drives = []
    for i, run in enumerate(runs):
        engine = StepEngine.over(batch.alone(i), goal_xy=run.goal_xy, measure=True)
        own = threshold if run.threshold is None else run.threshold
        policy = behaving_policy(robot, run.fam, run.behaviour, method, own)
        drives.append(Drive(engine, policy, minutes, run.on_step))
    return drive_together(batch, drives)


def behaving_policy(
    robot: RobotConfig,
    fam: VelocityPerception,
    behaviour: str,
    method: Method,
    threshold: float,
) -> Policy:
    """The TVL policy over `fam` (or a reference that perceives as one), perceiving through
    the method's echo memory and finding walls by its wall rule, inside its reflexes."""
    perception = Perception(method.memory, robot, seeking_goal=behaviour == "goal")
    tvl = TvlPolicy(fam, robot, behaviour, threshold, perception, method.wall_rule)
    return wrap(tvl, method.reflexes, robot, behaviour)
