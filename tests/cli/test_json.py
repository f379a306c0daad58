"""`--json` on every command that reports something: one JSON document on stdout, following
the schema the package ships for it, on the command line, run in process."""

from __future__ import annotations

import hashlib
from pathlib import Path

import click
import pytest
from conftest import invoke
from json_schemas import ENVELOPE, valid
from test_bad_numbers import SQUARE

from tvl_cli.cli.main import COMMANDS, command_named
from tvl_cli.core.fam_config import DESIGNED

COUNTS = {"segments", "discs", "rings", "goals"}


def tvl_json(command: str, *args: str | Path) -> dict:
    """What `tvl COMMAND ARGS --json` printed, once it is found to follow its schema."""
    done = invoke(*command.split(), *args, "--json")
    assert done.returncode == 0, done.stderr
    return valid(command, done.stdout)


@pytest.fixture(scope="module")
def learnt(tmp_path_factory: pytest.TempPathFactory) -> Path:
    log = tmp_path_factory.mktemp("json") / "log.h5"
    printed = tvl_json("learn", SQUARE, "--log", log, "--minutes", "1")
    assert printed["status"] == "finished"
    return log


def test_world_commands_print_what_the_world_holds(tmp_path: Path) -> None:
    world, png = tmp_path / "rooms.txt", tmp_path / "rooms.png"
    made = tvl_json("world new", "rooms", "--seed", "3", "-o", world)
    assert made["outputs"] == {"world": str(world)}
    assert (made["inputs"]["kind"], made["inputs"]["seed"]) == ("rooms", 3)
    counts = made["counts"]
    assert counts.keys() == COUNTS and counts["segments"] > 4 and counts["goals"] >= 1
    read = {"path": str(world), "sha256": hashlib.sha256(world.read_bytes()).hexdigest()}
    checked = tvl_json("world check", world)
    assert (checked["inputs"]["world"], checked["ok"], checked["counts"]) == (read, True, counts)
    drawn = tvl_json("world render", world, "-o", png)
    assert (drawn["inputs"]["world"], drawn["counts"]) == (read, counts)
    assert drawn["outputs"] == {"picture": str(png)} and png.stat().st_size > 1000


def test_train_prints_its_summary(learnt: Path, tmp_path: Path) -> None:
    fam = tmp_path / "fam.h5"
    printed = tvl_json("train", learnt, "-o", fam, "--config", "multi")
    assert printed.keys() - ENVELOPE == {
        "config", "episodes", "exemplars", "rules_touched", "rules_total", "wall_s",
        "repeated_sessions",
    }  # fmt: skip
    assert printed["inputs"]["method"]["preset"] == "default"
    assert (printed["outputs"]["fam"], printed["config"]) == (str(fam), "multi")
    (log,) = printed["inputs"]["logs"]
    assert log == {"path": str(learnt), "sha256": hashlib.sha256(learnt.read_bytes()).hexdigest()}
    assert 0 < printed["rules_touched"] <= printed["rules_total"] and printed["exemplars"] > 0
    assert fam.exists()


def test_train_takes_the_designed_configuration_by_name(learnt: Path, tmp_path: Path) -> None:
    fam = tmp_path / "fam.h5"
    printed = tvl_json("train", learnt, "-o", fam, "--config", "designed")
    assert (printed["config"], printed["rules_total"]) == ("designed", DESIGNED.rule_count)
    assert tvl_json("inspect", fam)["config"]["name"] == "designed"


@pytest.mark.slow  # over a second: learns, runs or draws at length
def test_demo_prints_learning_and_every_run(tmp_path: Path) -> None:
    printed = tvl_json("demo", tmp_path / "demo")
    assert printed["learning"]["status"] == "finished"
    # The learning's minutes are learn's and replay's rows, of the same types.
    replayed = tvl_json("replay", printed["outputs"]["log"])
    assert replayed["minutes"] == printed["learning"]["minutes"]
    runs = printed["runs"]
    assert [(r["config"], r["behaviour"]) for r in runs] == [
        ("single", "avoid"), ("single", "wall-left"), ("multi", "avoid"), ("multi", "wall-left")
    ]  # fmt: skip
    for run in runs:
        assert run["contacts"] == run["collisions"] + run["near_misses"]
        assert Path(run["png"]).exists()


@pytest.mark.slow
def test_csv_rows_of_rules_and_of_run_metrics(learnt: Path, tmp_path: Path) -> None:
    import csv
    import io

    fam = tmp_path / "multi.h5"
    tvl_json("train", learnt, "-o", fam, "--config", "multi")
    listed = invoke("inspect", fam, "--top", "5", "--csv")
    rows = list(csv.DictReader(io.StringIO(listed.stdout)))
    assert len(rows) == 5 and {"trajectory", "velocity_mps", "experience"} <= rows[0].keys()
    # Each table of the multi FAM has its own inputs: a row leaves the others' empty.
    assert all(0 < sum(bool(v) for v in row.values()) < len(row) for row in rows)
    ran = invoke("run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "0.2", "--csv")
    (row,) = csv.DictReader(io.StringIO(ran.stdout))
    assert float(row["sim_s"]) == 12.0 and row["mean_wall_clearance_m"] == ""
    both = invoke("run", fam, SQUARE, "--behaviour", "avoid", "--csv", "--json")
    assert both.returncode == 2 and "give --json or --csv, not both" in both.stderr


def _leaf_commands() -> list[tuple[str, click.Command]]:
    """Every command a user can run, subcommands of a group by their full name."""
    found = []
    for name in COMMANDS:
        command = command_named(name)
        if isinstance(command, click.Group):
            found += [(f"{name} {sub}", c) for sub, c in command.commands.items()]
        else:
            found.append((name, command))
    return found


@pytest.mark.parametrize("name, command", _leaf_commands(), ids=lambda v: str(v))
def test_every_command_takes_json(name: str, command: click.Command) -> None:
    assert "--json" in {opt for p in command.params for opt in p.opts}, name
