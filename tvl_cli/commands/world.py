"""`tvl world new`, `check`, `show` and `render`: world files made, read and drawn.

(`tvl world import` and `tvl world export`, to and from occupancy grids, are
commands/world_import.py and commands/world_export.py.)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.json_documents import document, input_file, world_input
from tvl_cli.sim.worldgen import Materials, generate_world
from tvl_cli.sim.worldmap import WorldMap, load_world, parse_world, world_of, world_to_dict


@dataclass(frozen=True, slots=True)
class NewWorldRequest:
    kind: str  # one of sim.worldgen.KINDS
    output: Path
    width_m: float | None  # None: the kind's own size
    height_m: float | None
    seed: int
    materials: Materials
    force: bool = False  # replace an existing output


def counts(world: WorldMap) -> dict[str, int]:
    """What a world holds, by kind (the keys of `world check --json`)."""
    return {
        "segments": len(world.segments),
        "discs": len(world.discs),
        "rings": len(world.rings),
        "goals": len(world.goals),
    }


@dataclass(frozen=True, slots=True)
class NewWorld:
    """A world generated and written, and what it holds."""

    request: NewWorldRequest
    counts: dict[str, int]

    def document(self) -> dict[str, Any]:
        r = self.request
        inputs = {
            "kind": r.kind,
            "width_m": r.width_m,
            "height_m": r.height_m,
            "seed": r.seed,
            "rough_share": r.materials.share,
            "roughness": r.materials.roughness,
        }
        return document("world new", inputs, outputs={"world": str(r.output)}, counts=self.counts)


@dataclass(frozen=True, slots=True)
class CheckedWorld:
    """A world file that reads as a world, and what it holds."""

    path: Path
    counts: dict[str, int]

    def document(self) -> dict[str, Any]:
        return document(
            "world check", {"world": input_file(self.path)}, ok=True, counts=self.counts
        )


@dataclass(frozen=True, slots=True)
class ShownWorld:
    """A world, read and checked (or made here), for its summary or its geometry to be shown."""

    given: Path | WorldMap  # a world file, or a world made here (`KIND:SEED`)
    world: WorldMap

    def document(self) -> dict[str, Any]:
        return document(
            "world show", {"world": world_input(self.given)}, world=world_to_dict(self.world)
        )


@dataclass(frozen=True, slots=True)
class RenderedWorld:
    """A world drawn as a picture, and what it holds."""

    given: Path | WorldMap  # a world file, or a world made here (`KIND:SEED`)
    output: Path
    counts: dict[str, int]

    def document(self) -> dict[str, Any]:
        return document(
            "world render",
            {"world": world_input(self.given)},
            outputs={"picture": str(self.output)},
            counts=self.counts,
        )


def new_world(request: NewWorldRequest) -> NewWorld:
    """Generate a world of the request's kind and write it."""
    text = generate_world(
        request.kind, request.width_m, request.height_m, request.seed, request.materials
    )
    with atomic_output(request.output, overwrite=request.force) as temporary:
        temporary.write_text(text, encoding="utf-8")
    return NewWorld(request, counts(parse_world(text, str(request.output))))


def check_world(path: Path) -> CheckedWorld:
    """What a world file holds; BadInput naming the problem if it is not a world."""
    return CheckedWorld(path, counts(load_world(path)))


def show_world(given: Path | WorldMap) -> ShownWorld:
    return ShownWorld(given, world_of(given))


def render_world(given: Path | WorldMap, output: Path) -> RenderedWorld:
    """Draw a world as a picture at `output`."""
    from tvl_cli.render.plot import render_world as draw  # matplotlib only when drawing

    world = world_of(given)
    draw(world, output)
    return RenderedWorld(given, output, counts(world))
