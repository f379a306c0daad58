"""The paper's TVL policy on a real simulated robot: runs that repeat exactly, and what it
does with no reflex to help it."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from tvl_cli.agent.drive import Step
from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.explore import Learner
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT, DEFAULT_REFLEXES
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.worldmap import WorldMap, parse_world

ROBOT = RobotConfig()
LIVE_RING = replace(DEFAULT, memory=NO_MEMORY)  # our method, perceiving the live ring
# A hall 7.5 m long with its north wall's face at y = 2.0 m and south wall's at y = 0.25 m.
HALL = parse_world(
    "version: 1\nname: hall\ncell: 0.25\n\n"
    + "#" * 32
    + "\n"
    + ("#" + "." * 30 + "#\n") * 2
    + "#.>"
    + "." * 28
    + "#\n"
    + ("#" + "." * 30 + "#\n") * 4
    + "#" * 32
    + "\n",
    "hall",
)
Y_M = 1.45  # the robot's centre: its edge 0.35 m from the north wall, 1.0 m from the south


def learnt_fam(world: WorldMap) -> Fam:
    fam = Fam(SINGLE, [t.name for t in ROBOT.trajectories])
    learner = Learner(world, ROBOT, fam, LearnParams(minutes=2.0), LIVE_RING, seed=3)
    learner.run(lambda _episode: None, lambda _minute: None)
    return fam


def fast_everywhere_fam() -> Fam:
    """A FAM that perceives every trajectory at its maximum, whatever the ring reads."""
    return Fam(SINGLE, [t.name for t in ROBOT.trajectories], max(ROBOT.v_max_mps))


def run(
    world: WorldMap,
    fam: Fam,
    behaviour: str,
    minutes: float,
    seed: int = 1,
    reflexes: tuple[str, ...] = DEFAULT_REFLEXES,
    **options,
) -> tuple[object, list[Step]]:
    steps: list[Step] = []
    method = replace(LIVE_RING, reflexes=reflexes)
    metrics = behave(
        world,
        ROBOT,
        fam,
        behaviour,
        minutes=minutes,
        seed=seed,
        on_step=steps.append,
        method=method,
        **options,
    )
    return metrics, steps


@pytest.mark.slow
@pytest.mark.parametrize("behaviour", ["avoid", "wall-left", "goal"])
@pytest.mark.parametrize("reflexes", [(), ("blocked-ways", "near-miss", "bump", "tie")])
def test_the_same_world_seed_and_options_give_the_same_run(behaviour, reflexes) -> None:
    fam = learnt_fam(HALL)
    goal = (6.0, 1.0) if behaviour == "goal" else None
    first, first_steps = run(HALL, fam, behaviour, 0.5, 5, goal_xy=goal, reflexes=reflexes)
    second, second_steps = run(HALL, fam, behaviour, 0.5, 5, goal_xy=goal, reflexes=reflexes)
    assert first == second
    assert [s.pose for s in first_steps] == [s.pose for s in second_steps]
    assert first.distance_m > 1.0  # the robot went somewhere


@pytest.mark.slow
def test_another_seed_gives_another_run() -> None:
    fam = learnt_fam(HALL)
    _, first = run(HALL, fam, "avoid", 0.5, 5)
    _, second = run(HALL, fam, "avoid", 0.5, 6)
    assert [s.pose for s in first] != [s.pose for s in second]


class EveryView:
    """A FAM that perceives every view on every step, as the rule did before it perceived the
    view ahead first: its view ahead alone reads nothing fast. Counts the steps it perceives
    every view on."""

    def __init__(self, fam: Fam, lazy: bool) -> None:
        self.fam, self.lazy, self.every_view_steps = fam, lazy, 0

    def perceive(self, ring_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        self.every_view_steps += 1
        return self.fam.perceive(ring_m)

    def perceive_ahead(self, ring_m: np.ndarray) -> np.ndarray:
        if self.lazy:
            return self.fam.perceive_ahead(ring_m)
        return np.zeros(len(ROBOT.trajectories))


@pytest.mark.slow
@pytest.mark.parametrize(
    ("behaviour", "reflexes"),
    [("avoid", DEFAULT_REFLEXES), ("wall-left", ()), ("goal", (*DEFAULT_REFLEXES, "goal-ward"))],
)
def test_perceiving_the_view_ahead_first_chooses_as_perceiving_every_view(
    behaviour: str, reflexes: tuple[str, ...]
) -> None:
    fam = learnt_fam(HALL)
    goal = (6.0, 1.0) if behaviour == "goal" else None
    runs = {}
    for lazy in (True, False):
        counting = EveryView(fam, lazy)
        metrics, steps = run(HALL, counting, behaviour, 1.0, 5, goal_xy=goal, reflexes=reflexes)
        runs[lazy] = (metrics, [(s.pose, s.decision.command) for s in steps], counting)
    assert runs[True][:2] == runs[False][:2]
    decisions = runs[False][2].every_view_steps
    if behaviour == "goal":  # the goal-ward advice reads every view whenever it is given
        assert runs[True][2].every_view_steps == decisions
    else:
        assert runs[True][2].every_view_steps < decisions / 2


# Straight down the hall at T0's 0.6 m/s, the body's edge meets the east wall after 11.5 s.
TO_THE_END_WALL_MIN = 12.0 / 60.0


def test_the_paper_policy_alone_drives_on_into_what_it_perceives_as_fast() -> None:
    metrics, steps = run(HALL, fast_everywhere_fam(), "avoid", 15.0 / 60.0, reflexes=())
    # One approach into the blind zone that ended touching: one contact, a collision.
    assert (metrics.collisions, metrics.near_misses, metrics.contacts) == (1, 0, 1)
    assert metrics.backoffs == 0
    assert all(s.decision.reflex == "" for s in steps)
    # It keeps choosing T0 against the wall: nothing in the paper's rule backs it off.
    assert steps[-1].decision.trajectory == 3 and steps[-1].bumped


@pytest.mark.slow
def test_every_step_records_the_view_the_choice_was_made_in() -> None:
    _, steps = run(HALL, learnt_fam(HALL), "avoid", 0.5, reflexes=())
    chosen = [s.decision for s in steps if s.decision.choice >= 0]
    assert chosen
    for d in chosen:
        assert d.velocities is not None and d.fast is not None
        # The choice is fast in its view, unless nothing is (then the robot is trapped).
        assert d.fast[d.choice]
        assert d.velocities[d.choice] >= 0.85 * ROBOT.v_max_mps[d.choice] - 1e-12


@pytest.mark.slow
def test_a_rotated_choice_spins_before_it_follows() -> None:
    _, steps = run(HALL, learnt_fam(HALL), "wall-left", 1.0, reflexes=())
    rotated = [i for i, s in enumerate(steps) if s.decision.rotation != 0]
    assert rotated, "the wall follower never rotated its perception"
    first = steps[rotated[0]].decision
    assert first.trajectory == -1 and first.command.linear_mps == 0.0
    assert "spin" in steps[rotated[0]].events
