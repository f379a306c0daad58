"""The contact autopsy on real runs: a smooth wall met at a slant is unheard, a wall met head
on was heard and rated fast, and a run's time is accounted for to the step."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from autopsy_rooms import NAMES, ROBOT, START_Y, room_with
from click.testing import CliRunner
from json_schemas import valid
from method_samples import LIVE_RING

from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.trace import Columns, TraceRecorder
from tvl_cli.analysis.autopsy import (
    BLIND_ZONE,
    NOT_GIVEN,
    RATED_FAST,
    REFLEX,
    SPINNING,
    TIME_CLASSES,
    ContactFacts,
    cause_of,
)
from tvl_cli.cli.main import main as cli
from tvl_cli.commands.contact_autopsy import run_autopsy
from tvl_cli.core.contacts import BUMP
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT
from tvl_cli.io.famfile import write_fam
from tvl_cli.sim.worldmap import WorldMap


def slanted_wall() -> tuple[float, float, float, float]:
    """A thin wall crossing the robot's path at 15°, ending before the point of it square to
    the robot comes onto it: met on its face, and heard square on only as the body touches."""
    crossing = np.array([6.0, START_Y + 0.125])
    back = np.array([math.cos(math.radians(165.0)), math.sin(math.radians(165.0))])
    start, end = crossing - 1.0 * back, crossing + 1.0 * back
    return (*start, *end)


def fast_fam() -> Fam:
    """Every trajectory perceived at its maximum, whatever the ring reads."""
    rules = SINGLE.tables[0].rule_count
    velocity = np.tile(np.array(ROBOT.v_max_mps), (rules, 1))  # (rules, 7) m/s
    return Fam.from_tables(SINGLE, NAMES, [velocity], [np.ones_like(velocity)])


def driven(world: WorldMap, minutes: float) -> tuple[Columns, object]:
    chunks: list[Columns] = []
    recorder = TraceRecorder((), ROBOT.sonar.count, [chunks.append])
    # The paper's choice rule alone, on the live ring.
    method = replace(DEFAULT, reflexes=(), memory=NO_MEMORY)
    metrics = behave(
        world, ROBOT, fast_fam(), "avoid", minutes=minutes, seed=1, on_step=recorder, method=method
    )
    recorder.close()
    return {k: np.concatenate([c[k] for c in chunks]) for k in chunks[0]}, metrics


def autopsy_of(world: WorldMap, columns: Columns):
    return run_autopsy(
        world,
        ROBOT,
        columns,
        reflex_names=(),
        trajectory_names=NAMES,
        table_sonars=None,
        goal_xy=None,
        goal_reached=False,
    )


def test_a_smooth_wall_met_at_a_slant_is_an_unheard_slant() -> None:
    world = room_with(slanted_wall())
    columns, metrics = driven(world, minutes=0.2)
    assert metrics.collisions >= 1
    first = autopsy_of(world, columns).contacts[0]
    assert first.facts.event == BUMP
    assert first.facts.obstacle == "slant"
    assert first.facts.trajectory == "T0"
    assert not first.facts.heard
    assert first.cause == "unheard-slant"


def test_a_wall_met_head_on_was_heard_and_rated_fast() -> None:
    world = room_with((6.0, 1.5, 6.0, 4.5))
    columns, metrics = driven(world, minutes=0.2)
    assert metrics.contacts >= 1
    first = autopsy_of(world, columns).contacts[0]
    assert first.facts.obstacle == "slant"  # the wall's face, square on
    assert first.facts.heard and first.facts.given and first.facts.given_beyond_blind_zone
    assert first.cause == RATED_FAST


def test_every_contact_of_a_run_gets_a_cause_and_every_step_a_time_class() -> None:
    world = room_with(slanted_wall())
    columns, metrics = driven(world, minutes=1.0)
    autopsy = autopsy_of(world, columns)
    assert len(autopsy.contacts) == metrics.contacts
    assert sum(autopsy.causes.values()) == metrics.contacts
    assert set(autopsy.time_s) == set(TIME_CLASSES)
    assert sum(autopsy.time_s.values()) == pytest.approx(metrics.sim_s)


def facts(**given: object) -> ContactFacts:
    base: dict[str, object] = {
        "step": 10,
        "time_s": 1.1,
        "event": BUMP,
        "obstacle": "edge",
        "driver": "policy",
        "reflex": None,
        "trajectory": "T0",
        "heard": True,
        "given": True,
        "given_beyond_blind_zone": True,
    }
    return ContactFacts(**{**base, **given})  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("given", "cause"),
    [
        ({"driver": REFLEX, "reflex": "bump", "heard": False}, REFLEX),
        ({"driver": SPINNING}, SPINNING),
        ({"heard": False, "given": False}, "unheard-edge"),
        ({"given": False}, NOT_GIVEN),
        ({"given_beyond_blind_zone": False}, BLIND_ZONE),
        ({}, RATED_FAST),
    ],
)
def test_the_first_cause_that_fits_is_taken(given: dict[str, object], cause: str) -> None:
    assert cause_of(facts(**given)) == cause


def test_explain_contacts_reads_a_trace_file(tmp_path: Path) -> None:
    world_file = tmp_path / "room.txt"
    world_file.write_text(room_with(slanted_wall()).text, encoding="utf-8")
    fam_file = tmp_path / "fast.h5"
    write_fam(fam_file, fast_fam(), robot_config=ROBOT, method=LIVE_RING, provenance={})
    trace = tmp_path / "run.h5"
    runner = CliRunner()
    ran = runner.invoke(
        cli,
        [
            "run",
            str(fam_file),
            str(world_file),
            "--behaviour",
            "avoid",
            "--minutes",
            "0.5",
            "--paper",
            "--log",
            str(trace),
            "--json",
        ],
    )
    assert ran.exit_code == 0, ran.output
    contacts = valid("run", ran.output)["contacts"]
    shown = runner.invoke(cli, ["explain", str(trace), "--contacts", "--json"])
    assert shown.exit_code == 0, shown.output
    printed = valid("explain", shown.output)
    assert printed["step"] is None and printed["inputs"]["contacts"]
    autopsy = printed["autopsy"]
    assert sum(c["contacts"] for c in autopsy["causes"]) == contacts
    assert len(autopsy["contacts"]) == contacts >= 1
    assert autopsy["contacts"][0]["cause"] == "unheard-slant"
    table = runner.invoke(cli, ["explain", str(trace), "--contacts"])
    assert "unheard-slant" in table.output and "where the time went" in table.output
    refused = runner.invoke(cli, ["explain", str(trace), "--contacts", "--step", "3"])
    assert refused.exit_code == 2
