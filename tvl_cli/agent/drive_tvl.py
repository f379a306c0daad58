"""A behaviour run: the paper's TVL policy inside a method's reflexes, driven from the
world's start for some simulated minutes."""

from __future__ import annotations

from tvl_cli.agent.drive import StepSink, drive_engine
from tvl_cli.agent.engine import StepEngine
from tvl_cli.agent.perception import Perception
from tvl_cli.agent.reflexes import wrap
from tvl_cli.agent.tvl import TvlPolicy
from tvl_cli.core.fam import Fam
from tvl_cli.core.method import Method
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.trajectory_choice import DEFAULT_THRESHOLD
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
) -> RunMetrics:
    """Perform `behaviour` with a FAM by `method`'s choices of behaving: perceiving through
    its echo memory, finding walls by its wall rule, inside its reflexes. The simulator's
    generator is seeded with `seed`."""
    engine = StepEngine(world, robot, goal_xy=goal_xy, measure=True)
    engine.reset(seed)
    perception = Perception(method.memory, robot)
    tvl = TvlPolicy(fam, robot, behaviour, threshold, perception, method.wall_rule)
    policy = wrap(tvl, method.reflexes, robot, behaviour)
    return drive_engine(engine, policy, minutes, on_step=on_step)
