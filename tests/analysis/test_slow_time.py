"""Why a run drove slowly, on real runs: every slow step of the policy gets one cause; a FAM
that rates every way slow is at fault by what it learnt in an open room, and not in a box
too small for any way to be fast."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from autopsy_rooms import NAMES, ROBOT, room_with

from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.trace import Columns, TraceRecorder
from tvl_cli.agent.true_velocities import TrueVelocities
from tvl_cli.analysis.autopsy import (
    FAST_DRIVE_MPS,
    LEARNT,
    MEMORY,
    RULE,
    SLOW_CAUSES,
    TIGHT,
    UNRATED,
    slow_cause,
)
from tvl_cli.analysis.slow_time import slow_time_by_cause
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT
from tvl_cli.sim.worldmap import WorldMap, parse_world

# The paper's choice rule alone, on the live ring.
LIVE = replace(DEFAULT, reflexes=(), memory=NO_MEMORY)


def slow_fam() -> Fam:
    """Every trajectory perceived at a tenth of its maximum, whatever the ring reads."""
    rules = SINGLE.tables[0].rule_count
    velocity = np.tile(0.1 * np.array(ROBOT.v_max_mps), (rules, 1))  # (rules, 7) m/s
    return Fam.from_tables(SINGLE, NAMES, [velocity], [np.ones_like(velocity)])


def driven(world: WorldMap, fam: Fam, minutes: float) -> Columns:
    chunks: list[Columns] = []
    recorder = TraceRecorder((), ROBOT.sonar.count, [chunks.append])
    behave(world, ROBOT, fam, "avoid", minutes=minutes, seed=1, on_step=recorder, method=LIVE)
    recorder.close()
    return {k: np.concatenate([c[k] for c in chunks]) for k in chunks[0]}


def slow_seconds(world: WorldMap, columns: Columns, fam: Fam | None) -> dict[str, float]:
    poses_before = np.vstack([np.array(world.start)[None, :], columns["pose"][:-1]])
    truth = TrueVelocities(world, ROBOT, LIVE)
    return slow_time_by_cause(
        ROBOT, DEFAULT_THRESHOLD, columns, poses_before, lambda pose: truth.in_view(pose, 0), fam
    )


def policy_slow_s(columns: Columns) -> float:
    slow = (columns["reflex"] < 0) & (columns["speed_mps"] < FAST_DRIVE_MPS)
    return float(slow.sum()) * ROBOT.control_period_s


def test_a_fam_that_rates_every_way_slow_in_an_open_room_is_at_fault_by_what_it_learnt() -> None:
    world = room_with((9.0, 0.5, 9.0, 1.0))  # a stub of wall far from the start
    columns = driven(world, slow_fam(), minutes=0.3)
    seconds = slow_seconds(world, columns, slow_fam())
    assert sum(seconds.values()) == pytest.approx(policy_slow_s(columns))
    assert seconds[LEARNT] >= 0.9 * sum(seconds.values()) > 0
    assert seconds[MEMORY] == 0.0  # read through no memory: nothing remembered closed a way


def test_in_a_box_too_small_for_any_way_to_be_fast_slow_was_right() -> None:
    rows = ["#######", *(["#.....#"] * 2), "#..>..#", *(["#.....#"] * 2), "#######"]
    world = parse_world("cell: 0.25\n" + "\n".join(rows) + "\n", "box")
    columns = driven(world, slow_fam(), minutes=0.2)
    seconds = slow_seconds(world, columns, slow_fam())
    slow_s = policy_slow_s(columns)
    assert slow_s > 0 and sum(seconds.values()) == pytest.approx(slow_s)
    assert seconds[TIGHT] == pytest.approx(slow_s)


def test_without_the_fam_what_it_learnt_and_what_it_remembered_go_unrated() -> None:
    world = room_with((9.0, 0.5, 9.0, 1.0))
    columns = driven(world, slow_fam(), minutes=0.3)
    seconds = slow_seconds(world, columns, None)
    assert seconds[LEARNT] == seconds[MEMORY] == 0.0
    assert seconds[UNRATED] >= 0.9 * sum(seconds.values()) > 0


NONE, FIRST, SECOND = (np.array(m, dtype=bool) for m in ([0, 0], [1, 0], [0, 1]))


@pytest.mark.parametrize(
    ("truly", "read", "live", "cause"),
    [
        (NONE, FIRST, FIRST, TIGHT),
        (FIRST, FIRST, NONE, RULE),
        (FIRST, SECOND, FIRST, MEMORY),
        (FIRST, SECOND, SECOND, LEARNT),
        (FIRST, NONE, None, UNRATED),
    ],
)
def test_the_first_slow_cause_that_fits_is_taken(
    truly: np.ndarray, read: np.ndarray, live: np.ndarray | None, cause: str
) -> None:
    assert cause in SLOW_CAUSES
    assert slow_cause(truly, read, live) == cause
