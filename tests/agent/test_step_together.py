"""Many engines stepped together over one RobotBatch in real pymunk worlds: each engine's
outcomes are, bit for bit, those of a lone engine with its seed and its commands."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from tvl_cli.agent.engine import StepEngine, StepOutcome, hold_together, step_together
from tvl_cli.core.contacts import BUMP, TRAPPED
from tvl_cli.core.drive_command import Command
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.batch import RobotBatch
from tvl_cli.sim.worldmap import WorldMap, load_world

ROOT = Path(__file__).resolve().parents[2]
ROBOT = RobotConfig()
OBSTACLES = load_world(ROOT / "worlds" / "obstacles.txt")
SEEDS = (3, 4, 5)
FORWARD, LEFT, SPIN = Command(0.5, 0.0), Command(0.4, 0.5), Command.spin(1.0)
BACK = Command(-0.2, 0.0)


def engines_over_a_batch(world: WorldMap) -> tuple[RobotBatch, list[StepEngine]]:
    """One engine a robot of a batch seeded with SEEDS, measuring its clearance."""
    batch = RobotBatch(world, ROBOT, [np.random.default_rng(seed) for seed in SEEDS])
    return batch, [StepEngine.over(batch.alone(i), measure=True) for i in range(batch.count)]


def lone_engine(world: WorldMap, seed: int) -> StepEngine:
    engine = StepEngine(world, ROBOT, measure=True)
    engine.reset(seed)
    return engine


def seen(outcome: StepOutcome) -> tuple:
    """An outcome as bytes and values: the ring before the step (None: not read), what the
    robot knows after it, the truth, the events and done."""
    after = outcome.observation
    return (
        None if outcome.ring_m is None else outcome.ring_m.tobytes(),
        after.time_s,
        after.odometry,
        after.bumped,
        outcome.truth,
        outcome.events,
        outcome.done,
    )


def test_engines_stepped_together_see_what_each_sees_alone() -> None:
    # Robot 1 reads its ring every step from a ring read ahead, robot 2 every step alone;
    # robot 0's is read ahead on odd steps and taken only when its judge wants it (driving
    # forward, not spinning), else given back undrawn.
    plans = [
        [FORWARD] * 10 + [SPIN] * 10 + [FORWARD] * 20,
        [LEFT] * 40,
        [SPIN] * 20 + [FORWARD] * 20,
    ]
    batch, engines = engines_over_a_batch(OBSTACLES)
    together: list[list[tuple]] = [[] for _ in SEEDS]
    for k in range(40):
        batch.read_ahead([0, 1] if k % 2 else [1])
        for engine in engines[1:]:
            engine.observation.ring.get()
        outcomes = step_together(batch, engines, [plan[k] for plan in plans])
        for steps, outcome in zip(together, outcomes, strict=True):
            assert outcome is not None
            steps.append(seen(outcome))
    for seed, plan, steps in zip(SEEDS, plans, together, strict=True):
        alone = lone_engine(OBSTACLES, seed)
        for command, step in zip(plan, steps, strict=True):
            if step[0] is not None:  # the ring was read before the step
                alone.observation.ring.get()
            assert seen(alone.step(command)) == step
    assert any(BUMP in step[5] for steps in together for step in steps)
    assert any(together[0][k][0] is None for k in range(1, 40, 2))  # untaken ahead of a spin


def test_a_robot_without_a_command_sits_the_step_out_untouched() -> None:
    batch, engines = engines_over_a_batch(OBSTACLES)
    resting = engines[1].observation
    outcomes = step_together(batch, engines, [FORWARD, None, SPIN])
    assert outcomes[1] is None
    assert engines[1].observation is resting
    assert batch.time_s.tolist() == [ROBOT.control_period_s, 0.0, ROBOT.control_period_s]
    assert engines[1].sim.pose == OBSTACLES.start


def test_a_trapped_robot_is_judged_trapped_and_the_others_not() -> None:
    batch, engines = engines_over_a_batch(OBSTACLES)
    outcomes = step_together(batch, engines, [SPIN] * 3, trapped=[False, True, False])
    assert [TRAPPED in outcome.events for outcome in outcomes if outcome] == [False, True, False]


def test_engines_holding_plans_together_end_where_each_ends_alone() -> None:
    # Plans of different lengths, one empty: a robot whose plan is done sits the rest out.
    plans = [[BACK] * 6, [SPIN] * 2 + [BACK] * 2, []]
    batch, engines = engines_over_a_batch(OBSTACLES)
    hold_together(batch, engines, plans)
    for seed, plan, engine in zip(SEEDS, plans, engines, strict=True):
        alone = lone_engine(OBSTACLES, seed)
        for command in plan:
            alone.step(command)
        assert engine.sim.time_s == alone.sim.time_s == len(plan) * ROBOT.control_period_s
        assert (engine.sim.pose, engine.sim.odometry) == (alone.sim.pose, alone.sim.odometry)
        assert engine.observation.ring_m.tobytes() == alone.observation.ring_m.tobytes()
