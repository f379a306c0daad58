"""One JSON Schema per command that prints JSON, shipped in the package and printed by
`tvl schema`; and every command's `--json` document, made for real in-process, following it."""

from __future__ import annotations

import copy
import fnmatch
import hashlib
import json
import re
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner
from json_schemas import StrictValidator, valid
from jsonschema import Draft202012Validator
from test_json import _leaf_commands

from tvl_cli.cli.main import main
from tvl_cli.io.json_documents import (
    SCHEMA_COMMANDS,
    command_schema,
    load_schema,
    schema_name,
    schema_version,
)

if sys.version_info >= (3, 11):
    import tomllib
else:
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]
SCHEMAS = ROOT / "tvl_cli" / "schemas"
WORLDS = ROOT / "worlds"
EXAMPLE_LOG = ROOT / "logs" / "square-s1.h5"
SNAKE_CASE = re.compile(r"^[a-z][a-z0-9]*(_[a-z0-9]+)*$")
METHOD = {"$ref": "urn:tvl:schema:common#/$defs/method"}


def tvl(*args: object) -> tuple[int, str, str]:
    done = CliRunner().invoke(main, [str(a) for a in args])
    return done.exit_code, done.stdout, done.stderr


def tvl_json(command: str, *args: object) -> dict[str, Any]:
    """What `tvl COMMAND ARGS --json` printed, once it is found to follow its schema."""
    code, stdout, stderr = tvl(*command.split(), *args, "--json")
    assert code == 0, stderr
    return valid(command, stdout)


def test_each_command_that_prints_json_has_a_schema_and_no_schema_is_spare() -> None:
    assert sorted(name for name, _ in _leaf_commands()) == sorted(SCHEMA_COMMANDS)
    shipped = {path.name for path in SCHEMAS.glob("*.json")}
    named = {f"{schema_name(c)}.schema.json" for c in SCHEMA_COMMANDS}
    assert shipped == named | {"common.schema.json"}


def test_the_schemas_are_package_data() -> None:
    setup = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    patterns = setup["package-data"]["tvl_cli"]
    for path in SCHEMAS.glob("*.json"):
        inside = path.relative_to(ROOT / "tvl_cli").as_posix()
        assert any(fnmatch.fnmatch(inside, pattern) for pattern in patterns), inside


@pytest.mark.parametrize("command", SCHEMA_COMMANDS)
def test_each_schema_is_draft_2020_12_and_fixes_its_id_and_version(command: str) -> None:
    schema = command_schema(command)
    Draft202012Validator.check_schema(schema)
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    assert schema["$id"] == f"urn:tvl:schema:{schema_name(command)}"
    top = schema["properties"]
    assert top["schema"] == {"const": schema["$id"]}
    version = top["schema_version"]["const"]
    assert isinstance(version, int) and version >= 1
    assert {"schema", "schema_version", "tvl_version", "inputs"} <= set(schema["required"])
    # The method the robot followed, among the inputs of every command that learns, trains
    # or behaves, and of no other.
    inputs = top["inputs"]
    takes_one = command in TAKE_A_METHOD
    assert ("method" in inputs["properties"]) == ("method" in inputs["required"]) == takes_one
    if takes_one:
        assert inputs["properties"]["method"] == METHOD


# The commands that learn, train or behave, whose inputs hold the method they followed.
TAKE_A_METHOD = {
    "learn", "train", "design", "run", "baseline dwa", "baseline qlearn",
    "bench generalization",
}  # fmt: skip


# Each schema as it stands at its version, by a digest of the whole (the shared definitions it
# uses in):
# a schema changed without a new version would let two kinds of document claim one. To
# change a schema, raise its schema_version and record the new pair here.
RELEASED = {
    "world new": (1, "3e84142d3fce99e0"),
    "world show": (2, "c6b1620391536259"),
    "world check": (1, "6f4c73aa86b3aaf4"),
    "world render": (1, "73701f22a7db6b3d"),
    "world import": (2, "946b4da5d9420c27"),
    "world export": (1, "9e6559936de1d145"),
    "learn": (8, "d435fcef9a7ee66e"),
    "train": (6, "4c519cebb6586ab9"),
    "inspect": (7, "b761ed12a9416064"),
    "diff": (2, "73af06e71a481611"),
    "design": (4, "23733125d8f21025"),
    "run": (8, "72a18bdbfc39991a"),
    "replay": (7, "02bdc64bd0592dfd"),
    "explain": (3, "2c4ea7aab9d99ef8"),
    "demo": (2, "e70a1078cb6cfd9b"),
    "baseline dwa": (7, "55fe8ce7c9cf082f"),
    "baseline qlearn": (7, "33d00873fa6fbf5e"),
    "sweep": (3, "f25eea67f6259167"),
    "bench generalization": (6, "7e5001b3512041fc"),
    "bench claims": (1, "c574aae6e568d1f9"),
    "export": (1, "4a3407f1771e4ec1"),
    "figure": (1, "beee1067ca60bd82"),
    "schema": (1, "a22dca3802d3975b"),
}


@pytest.mark.parametrize("command", SCHEMA_COMMANDS)
def test_a_schema_changes_only_with_its_version(command: str) -> None:
    text = json.dumps(command_schema(command), sort_keys=True).encode()
    found = (schema_version(command), hashlib.sha256(text).hexdigest()[:16])
    assert found == RELEASED[command], (
        f"the schema of {command!r} is not the one recorded for its version: raise its "
        f"schema_version and record {found} in RELEASED"
    )


def _property_names(schema: Any) -> Iterator[str]:
    if isinstance(schema, dict):
        for key, value in schema.items():
            if key == "properties":
                yield from value
            yield from _property_names(value)
    elif isinstance(schema, list):
        for item in schema:
            yield from _property_names(item)


@pytest.mark.parametrize("command", SCHEMA_COMMANDS)
def test_every_key_a_schema_names_is_snake_case(command: str) -> None:
    names = set(_property_names(command_schema(command)))
    assert names and not {n for n in names if not SNAKE_CASE.match(n)}


def test_no_document_may_carry_a_key_its_schema_does_not_name() -> None:
    found = {"schema": "urn:tvl:schema:world-check", "schema_version": 1, "tvl_version": "0"}
    counts = {"segments": 1, "discs": 0, "rings": 0, "goals": 0}
    world = {"path": "w.txt", "sha256": "0" * 64}
    good = {**found, "inputs": {"world": world}, "ok": True, "counts": counts}
    assert valid("world check", good)
    for bad in (
        {**good, "file": "w.txt"},
        {**good, "counts": {**counts, "segments": 1.0}},  # a count is a whole number
        {**good, "inputs": {"world": {**world, "sha256": "abc"}}},
        {**good, "schema_version": 2},
    ):
        assert list(StrictValidator(command_schema("world check")).iter_errors(bad))


def test_schema_lists_each_command_with_its_id_and_version() -> None:
    code, stdout, _ = tvl("schema")
    assert code == 0
    lines = stdout.splitlines()
    assert [line.split("urn:")[0].strip() for line in lines] == list(SCHEMA_COMMANDS)
    assert "urn:tvl:schema:world-new  (version 1)" in lines[0]
    listed = tvl_json("schema")
    assert [row["command"] for row in listed["schemas"]] == list(SCHEMA_COMMANDS)
    assert listed["inputs"] == {"command": None} and "json_schema" not in listed


@pytest.mark.parametrize("typed", [["world", "new"], ["world-new"]])
def test_schema_prints_a_commands_schema_whole(typed: list[str], tmp_path: Path) -> None:
    code, stdout, _ = tvl("schema", *typed)
    assert code == 0
    printed = json.loads(stdout)
    assert printed == command_schema("world new")
    # Whole: the shared definitions it uses are in it, and no other (it holds no method), and
    # it checks a document with no other file.
    shared = printed["$defs"]["urn:tvl:schema:common"]["$defs"]
    assert set(shared) < set(load_schema("common")["$defs"])
    assert "seed" in shared and "method" not in shared
    checker = Draft202012Validator(printed)
    made = tvl_json("world new", "square", "-o", tmp_path / "w.txt")
    checker.validate(made)
    assert not checker.is_valid({**made, "counts": {**made["counts"], "goals": -1}})


def test_schema_json_carries_the_schema_in_a_document() -> None:
    printed = tvl_json("schema", "run")
    assert printed["inputs"] == {"command": "run"}
    assert printed["json_schema"] == command_schema("run")
    assert printed["schemas"] == [
        {"command": "run", "id": "urn:tvl:schema:run", "schema_version": schema_version("run")}
    ]


@pytest.mark.parametrize(
    "typed, hint",
    [
        ("rnu", " prints JSON (did you mean 'run'?)"),
        ("wrld new", " prints JSON (did you mean 'world new'?)"),
        ("frobnicate", " prints JSON (known: world new, world show, "),
    ],
)
def test_an_unknown_command_is_one_line_with_the_nearest_name(typed: str, hint: str) -> None:
    code, stdout, stderr = tvl("schema", *typed.split())
    assert (code, stdout) == (2, "")
    assert stderr.count("\n") == 1 and stderr.startswith(f"tvl: error: no command {typed!r}")
    assert hint in stderr


@pytest.fixture(scope="module")
def made(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A FAM trained from the example log, another from its first minutes, and a run's trace."""
    directory = tmp_path_factory.mktemp("documents")
    files = {
        "fam": directory / "fam.h5",
        "early": directory / "early.h5",
        "trace": directory / "run.h5",
        "directory": directory,
    }
    assert tvl("train", EXAMPLE_LOG, "-o", files["fam"])[0] == 0
    assert tvl("train", EXAMPLE_LOG, "-o", files["early"], "--until-minute", "2")[0] == 0
    ran = tvl(
        "run", files["fam"], WORLDS / "lab.txt", "--behaviour", "wall-left", "--paper",
        "--minutes", "0.5", "--log", files["trace"],
    )  # fmt: skip
    assert ran[0] == 0, ran[2]
    return files


def test_world_documents_follow_their_schemas(tmp_path: Path) -> None:
    world = tmp_path / "rooms.txt"
    made = tvl_json("world new", "rooms", "--size", "6", "5", "-o", world)
    assert (made["inputs"]["width_m"], made["inputs"]["height_m"]) == (6.0, 5.0)
    shown = tvl_json("world show", world)
    assert len(shown["world"]["segments"]) == made["counts"]["segments"]
    assert tvl_json("world check", world)["counts"] == made["counts"]
    exported = tvl_json("world export", world, "-o", tmp_path / "m.yaml")
    assert exported["inputs"]["world"] == shown["inputs"]["world"]
    x, y, heading = shown["world"]["start"]
    imported = tvl_json(
        "world import", tmp_path / "m.yaml", "-o", tmp_path / "back.txt", "--start",
        f"{x},{y},{heading:g}",
    )  # fmt: skip
    assert imported["start"] == [x, y, heading]  # the world's origin is the map's


def test_world_render_document_follows_its_schema(tmp_path: Path) -> None:
    drawn = tvl_json("world render", WORLDS / "lab.txt", "-o", tmp_path / "w.svg")
    assert drawn["outputs"] == {"picture": str(tmp_path / "w.svg")}


def test_learn_and_replay_give_a_minute_of_learning_the_same_types(tmp_path: Path) -> None:
    log = tmp_path / "log.h5"
    learnt = tvl_json("learn", WORLDS / "square.txt", "--log", log, "--minutes", "1")
    assert learnt["inputs"]["world"]["path"] == str(WORLDS / "square.txt")
    assert (learnt["inputs"]["seed"], learnt["inputs"]["minutes"]) == (1, 1.0)
    assert learnt["inputs"]["robot"] == "yamabico"
    replayed = tvl_json("replay", log)
    assert replayed["minutes"] == learnt["minutes"] and len(learnt["minutes"]) == 1
    row = replayed["minutes"][0]
    assert [type(row[k]) for k in ("minute", "episodes", "exemplars", "delta_v")] == [
        int, int, int, float
    ]  # fmt: skip
    (session,) = replayed["sessions"]
    assert (session["session"], session["episodes"]) == (learnt["session"], learnt["episodes"])


@pytest.mark.slow  # over a second
def test_fam_documents_follow_their_schemas(made: dict[str, Path]) -> None:
    trained = tvl_json("train", EXAMPLE_LOG, "-o", made["directory"] / "again.h5")
    assert trained["inputs"]["logs"][0]["path"] == str(EXAMPLE_LOG)
    listed = tvl_json("inspect", made["fam"], "--top", "3")
    assert len(listed["rules"]) == 3 and listed["explanation"] is None
    ring = ",".join(["0.5"] + ["2.0"] * 15)
    explained = tvl_json("inspect", made["fam"], "--explain", ring)
    assert explained["rules"] is None and explained["explanation"]["rules"]
    differing = tvl_json("diff", made["early"], made["fam"], "--top", "2")
    assert len(differing["rules_differing_most"]) == 2


@pytest.mark.slow  # over a second: draws two pictures
def test_inspect_records_the_inputs_its_picture_was_drawn_over(
    made: dict[str, Path], tmp_path: Path
) -> None:
    png = tmp_path / "surface.png"
    given = ("--over", "front,front-right", "--fix", "front-left=0.6", "--fix", "rear-left=1.5")
    drawn = tvl_json("inspect", made["fam"], "--png", png, *given, "--top", "1")
    assert drawn["outputs"]["png"] == str(png)
    assert drawn["inputs"]["over"] == ["front", "front-right"]
    assert drawn["inputs"]["fix"] == {"front-left": 0.6, "rear-left": 1.5}
    # Not given, the pair the picture was drawn over: the one most of the tables read.
    default = tvl_json("inspect", made["fam"], "--png", tmp_path / "d.png", "--top", "1")
    assert (default["inputs"]["over"], default["inputs"]["fix"]) == (["front", "front-left"], {})
    listed = tvl_json("inspect", made["fam"], "--top", "1")
    assert (listed["inputs"]["over"], listed["inputs"]["fix"]) == (None, {})


@pytest.mark.slow  # over a second
def test_design_document_follows_its_schema(tmp_path: Path) -> None:
    designed = tvl_json("design", EXAMPLE_LOG, "-o", tmp_path / "d.json", "--budget", "200")
    assert designed["outputs"]["config"] == str(tmp_path / "d.json")
    assert designed["inputs"]["budget_rules"] == 200 >= designed["rules"]


def test_run_documents_follow_their_schemas(made: dict[str, Path]) -> None:
    ran = tvl_json(
        "run", made["fam"], WORLDS / "square.txt", "--behaviour", "avoid", "--minutes", "0.2"
    )
    assert ran["inputs"]["fam"]["path"] == str(made["fam"])
    replayed = tvl_json("replay", made["trace"])
    assert replayed["parameters"]["fam"]["path"] == str(made["fam"])
    explained = tvl_json("explain", made["trace"], "--step", "3")
    assert explained["step"]["step"] == 3 and explained["autopsy"] is None
    autopsy = tvl_json("explain", made["trace"], "--contacts")
    assert autopsy["step"] is None and len(autopsy["autopsy"]["contacts"]) == sum(
        c["contacts"] for c in autopsy["autopsy"]["causes"]
    )
    exported = tvl_json("export", made["trace"], "--mcap", made["directory"] / "run.mcap")
    assert exported["steps"] == replayed["steps"]


def test_baseline_documents_follow_their_schemas() -> None:
    square = WORLDS / "square.txt"
    dwa = tvl_json("baseline dwa", square, "--minutes", "0.1", "--sensor", "ring")
    assert (dwa["inputs"]["sensor"], dwa["inputs"]["method"]["memory"]["kind"]) == ("ring", "none")
    qlearn = tvl_json("baseline qlearn", square, "--learn-minutes", "0.1", "--minutes", "0.1")
    assert qlearn["learn_minutes"] == qlearn["inputs"]["learn_minutes"] == 0.1


@pytest.mark.slow
def test_a_figure_document_follows_its_schema(made: dict[str, Path]) -> None:
    """A results file as the experiment scripts make one: each run's parameters, then what
    `tvl run --json` printed."""
    rows = []
    for minute, fam in ((2, made["early"]), (5, made["fam"])):
        printed = tvl_json(
            "run", fam, WORLDS / "square.txt", "--behaviour", "avoid", "--minutes", "0.1"
        )
        rows.append(
            {
                "kind": "tvl",
                "world": "square",
                "seed": 1,
                "config": "single",
                "minute": minute,
                **printed,
            }
        )
    results = made["directory"] / "results.jsonl"
    results.write_text("".join(json.dumps(row) + "\n" for row in rows))
    drawn = tvl_json("figure", "fig27", results, "-o", made["directory"] / "fig.png")
    assert drawn["summary_markdown"].startswith("### ") and drawn["outputs"]["table"] is None


def test_a_count_written_as_a_float_fails_the_check() -> None:
    """What holds every test above to one type a key: a minute written 0.0 for 0 fails."""
    printed = tvl_json("replay", EXAMPLE_LOG)
    changed = copy.deepcopy(printed)
    changed["minutes"][0]["minute"] = float(changed["minutes"][0]["minute"])
    with pytest.raises(AssertionError, match="minutes/0/minute"):
        valid("replay", changed)


def test_the_memory_schema_names_every_kind_and_clearing_the_memory_takes() -> None:
    from tvl_cli.core.memory import CLEARINGS, MEMORY_KINDS, MemoryConfig

    memory = load_schema("common")["$defs"]["memory"]
    assert tuple(memory["properties"]["kind"]["enum"]) == MEMORY_KINDS
    assert tuple(memory["properties"]["clearing"]["enum"]) == CLEARINGS
    assert set(memory["required"]) == set(MemoryConfig().to_dict())
