"""`tvl world new`, `check`, `show` and `render`: world files made, read and drawn.

(`tvl world import` and `tvl world export`, to and from occupancy grids, are
commands/world_import.py and commands/world_export.py.)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from tvl_cli.io.atomic import atomic_output
from tvl_cli.sim.worldgen import Materials, generate_world
from tvl_cli.sim.worldmap import WorldMap, load_world, parse_world


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


def new_world(request: NewWorldRequest) -> dict[str, int]:
    """Generate a world of the request's kind and write it; what it holds."""
    text = generate_world(
        request.kind, request.width_m, request.height_m, request.seed, request.materials
    )
    with atomic_output(request.output, overwrite=request.force) as temporary:
        temporary.write_text(text, encoding="utf-8")
    return counts(parse_world(text, str(request.output)))


def check_world(path: Path) -> dict[str, int]:
    """What a world file holds; BadInput naming the problem if it is not a world."""
    return counts(load_world(path))


def show_world(path: Path) -> WorldMap:
    """A world file, read and checked, for its summary or its geometry to be shown."""
    return load_world(path)


def render_world(path: Path, output: Path) -> dict[str, int]:
    """Draw a world file as a picture at `output`; what it holds."""
    from tvl_cli.render.plot import render_world as draw  # matplotlib only when drawing

    world = load_world(path)
    draw(world, output)
    return counts(world)
