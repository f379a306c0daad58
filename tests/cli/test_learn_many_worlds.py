"""`tvl learn WORLD...`: a session in each world, in one log, each going on from the last."""

from __future__ import annotations

import json
from pathlib import Path

from tvl_cli.io.logreader import read_log
from tvl_cli.sim.world_entries import MAX_GENERATED, named_worlds

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "worlds" / "square.txt"


def test_a_seed_range_and_a_file_learn_a_session_each_in_order(invoke_tvl, tmp_path) -> None:
    log = tmp_path / "many.h5"
    done = invoke_tvl(
        "learn", "rooms:11-12", SQUARE, "--log", log, "--minutes", "0.2", "--json"
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    documents = [json.loads(line) for line in done.stdout.splitlines()]
    assert [d["inputs"]["world"]["path"] for d in documents] == [
        "rooms-s11", "rooms-s12", str(SQUARE),
    ]  # fmt: skip
    sessions = read_log(log).sessions
    assert [s.world_name for s in sessions] == ["rooms-s11", "rooms-s12", "square"]
    # Each session goes on from those before it, on a random stream of its own.
    assert [s.parameters["seed_stream"] for s in sessions] == [0, 1, 2]
    # Several worlds asked for at once are meant: no warning that the log mixes them.
    assert done.stderr == ""


def test_a_generated_world_is_the_one_a_grid_or_tvl_world_new_makes(invoke_tvl, tmp_path) -> None:
    made = tmp_path / "rooms.txt"
    assert invoke_tvl("world", "new", "rooms", "--seed", "12", "-o", made).returncode == 0
    (generated,) = named_worlds("rooms:12")
    assert generated.world.text == made.read_text() and generated.path is None


def test_world_entries_that_name_no_world_are_refused_in_one_line(invoke_tvl, tmp_path) -> None:
    log = tmp_path / "none.h5"
    for entry, phrase in (
        ("rooms:x", "KIND:SEED or KIND:FIRST-LAST needs whole-number seeds"),
        ("rooms:5-3", "seeds from 5 to 3 are no range of seeds"),
        (f"rooms:1-{MAX_GENERATED + 1}", f"{MAX_GENERATED + 1:,} worlds; at most"),
        ("roms:3", "no world kind 'roms' (did you mean 'rooms'?)"),
        ("nowhere.txt", "no such world file nowhere.txt, nor KIND:SEED, nor a bundled world"),
    ):
        done = invoke_tvl("learn", entry, "--log", log, "--minutes", "0.1")
        assert done.returncode == 2, entry
        assert done.stderr.count("\n") == 1, done.stderr
        assert done.stderr.startswith(f"tvl: error: world {entry!r}: {phrase}")
    assert not log.exists()


def test_from_fam_starts_one_world(invoke_tvl, tmp_path) -> None:
    done = invoke_tvl(
        "learn", "rooms:1-2", "--log", tmp_path / "l.h5", "--from-fam", tmp_path / "f.h5"
    )  # fmt: skip
    assert done.returncode == 2 and "--from-fam starts a new log" in done.stderr
