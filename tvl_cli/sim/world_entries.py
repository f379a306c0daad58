"""Worlds as a user names them on a command line or in a grid: a world file, a generated
world (`KIND:SEED`, or `KIND:FIRST-LAST` for one world a seed), or a world bundled with tvl
by its name. Experience from many worlds starts here: `tvl learn rooms:11-20 --log LOG`
learns a session in each."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from tvl_cli.core.errors import MAX_SEED, BadInput, did_you_mean
from tvl_cli.sim.worldgen import KINDS, bundled_world_path, generate_world
from tvl_cli.sim.worldmap import WorldMap, load_world, parse_world

# A range of generated worlds is learnt one after another: more than this is a typing slip
# (a seed range of millions), not a plan.
MAX_GENERATED = 1000


@dataclass(frozen=True, slots=True)
class NamedWorld:
    """A world and how it was named: its file (None for a generated world)."""

    entry: str  # as given, or `KIND:SEED` for each world of a range
    world: WorldMap
    path: Path | None


def named_worlds(entry: str, folder: Path = Path(".")) -> list[NamedWorld]:
    """The worlds `entry` names, a file found in `folder` first; BadInput (beginning
    `world 'ENTRY':`) if it names none."""
    file = _named_file(entry, folder)
    if file is not None:
        return [NamedWorld(entry, load_world(file), file)]
    return [
        NamedWorld(f"{kind}:{seed}", _generated(kind, seed), None)
        for kind, seed in _kinds_and_seeds(entry)
    ]


def named_world(entry: str, folder: Path = Path(".")) -> Path | WorldMap:
    """The one world `entry` names, as `named_worlds` finds it: its file, which the command
    reads as it reads any world file (so it is not parsed here first), or the world made
    here; BadInput if it names a range of several, where a command drives in one world."""
    file = _named_file(entry, folder)
    if file is not None:
        return file
    made = _kinds_and_seeds(entry)
    if len(made) > 1:
        raise BadInput(f"world {entry!r}: {len(made)} worlds; name one (KIND:SEED)")
    return _generated(*made[0])


def _named_file(entry: str, folder: Path) -> Path | None:
    """The world file `entry` names (in `folder`, else bundled with tvl); None for a
    generated world (`KIND:...`); BadInput if it names none."""
    file = folder / entry
    if file.is_file():
        return file
    if ":" in entry:
        return None
    try:
        return bundled_world_path(entry)
    except BadInput:
        raise BadInput(
            f"world {entry!r}: no such world file {file}, nor KIND:SEED, nor a bundled world "
            f"({', '.join(KINDS)})"
        ) from None


def _kinds_and_seeds(entry: str) -> list[tuple[str, int]]:
    """The (kind, seed) of each generated world `KIND:SEED` or `KIND:FIRST-LAST` names."""
    kind, _, seeds = entry.partition(":")
    return [(kind, seed) for seed in _seeds(entry, kind, seeds)]


def _generated(kind: str, seed: int) -> WorldMap:
    return parse_world(generate_world(kind, None, None, seed), f"{kind}:{seed}")


def _seeds(entry: str, kind: str, seeds: str) -> range:
    if kind not in KINDS:
        known = did_you_mean(kind, list(KINDS))
        raise BadInput(f"world {entry!r}: no world kind {kind!r} ({known})")
    first, dash, last = seeds.partition("-")
    if not first.isdigit() or (dash and not last.isdigit()):
        raise BadInput(f"world {entry!r}: KIND:SEED or KIND:FIRST-LAST needs whole-number seeds")
    low, high = int(first), int(last) if dash else int(first)
    if high > MAX_SEED or high < low:
        raise BadInput(f"world {entry!r}: seeds from {low} to {high} are no range of seeds")
    if high - low + 1 > MAX_GENERATED:
        raise BadInput(
            f"world {entry!r}: {high - low + 1:,} worlds; at most {MAX_GENERATED:,} a range"
        )
    return range(low, high + 1)
