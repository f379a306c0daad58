"""Behaviour runs driven together in one RobotBatch give, run by run, what each gives driven
alone: the same metrics and the same trace, step for step, in a real pymunk world."""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path

import numpy as np
import pytest

from tvl_cli.agent.drive import Step
from tvl_cli.agent.drive_tvl import BehaviourRun, behave, behave_together
from tvl_cli.commands.train import train_from_logs
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.memory import NONE, MemoryChoice
from tvl_cli.core.method import DEFAULT, PAPER, Method, MethodChoice
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.worldmap import load_world

ROOT = Path(__file__).resolve().parents[2]
ROBOT = RobotConfig()
WORLD = load_world(ROOT / "worlds" / "square.txt")
MINUTES = 0.4


@pytest.fixture(scope="module")
def fams() -> tuple[Fam, Fam]:
    """Two FAMs from the example log: through our echo memory, and from the live ring."""
    log = [ROOT / "logs" / "square-s1.h5"]
    live_ring = MethodChoice(memory=MemoryChoice(NONE))
    return train_from_logs(log, SINGLE).fam, train_from_logs(log, SINGLE, live_ring).fam


def steps_of(step: Step) -> tuple:
    """A step as the trace keeps it: every value, the ring as bytes (None: not read)."""
    ring = None if step.ring_m is None else step.ring_m.tobytes()
    decision = tuple(
        getattr(step.decision, f.name) for f in fields(step.decision)
    )  # its arrays as bytes
    decision = tuple(v.tobytes() if isinstance(v, np.ndarray) else v for v in decision)
    return (step.time_s, ring, decision, step.pose, step.odometry, step.bumped, step.events)


@pytest.mark.slow
@pytest.mark.parametrize("method", [DEFAULT, PAPER], ids=["default", "paper"])
def test_runs_driven_together_are_the_runs_driven_alone(
    fams: tuple[Fam, Fam], method: Method
) -> None:
    ours, live = fams
    x, y, _ = WORLD.start
    near_goal = (x + 0.8, y)  # reached early: that robot sits the others' steps out
    plans = [
        (ours, "avoid", 1, None),
        (ours, "wall-left", 1, None),
        (live, "goal", 2, near_goal),
        (live, "avoid", 1, None),
    ]
    together: list[list[tuple]] = [[] for _ in plans]
    runs = [
        BehaviourRun(
            fam, behaviour, seed, goal, lambda step, seen=seen: seen.append(steps_of(step))
        )
        for (fam, behaviour, seed, goal), seen in zip(plans, together, strict=True)
    ]
    metrics = behave_together(WORLD, ROBOT, runs, minutes=MINUTES, method=method)
    for (fam, behaviour, seed, goal), seen, got in zip(plans, together, metrics, strict=True):
        alone: list[tuple] = []
        expected = behave(
            WORLD, ROBOT, fam, behaviour, minutes=MINUTES, seed=seed, method=method,
            goal_xy=goal, on_step=lambda step, alone=alone: alone.append(steps_of(step)),
        )  # fmt: skip
        assert got == expected
        assert seen == alone
    # The goal was reached well before the others finished; some steps read no ring.
    assert metrics[2].goal_reached and len(together[2]) < len(together[0]) == 240
    assert any(step[1] is None for seen in together for step in seen)
    assert len({np.float64(m.mean_speed_mps) for m in metrics}) > 1
