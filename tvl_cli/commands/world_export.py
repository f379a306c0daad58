"""`tvl world export`: a world -> a ROS map_server occupancy grid (YAML and PGM)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tvl_cli.core.errors import BadInput
from tvl_cli.io.json_documents import document, world_input
from tvl_cli.io.occupancy_map import write_occupancy_map
from tvl_cli.io.paths import refuse_output_among_inputs
from tvl_cli.sim.maps.raster import rasterise
from tvl_cli.sim.worldmap import WorldMap, world_of

YAML_SUFFIXES = (".yaml", ".yml")


@dataclass(frozen=True, slots=True)
class Exported:
    world: Path | WorldMap  # a world file, or a world made here (`KIND:SEED`)
    map_yaml: Path
    image: Path
    cell_m: float
    columns: int
    rows: int
    free_cells: int
    occupied_cells: int

    def to_dict(self) -> dict[str, object]:
        """What was written, in cells (the files are the command's outputs)."""
        return {
            "cell_m": self.cell_m,
            "columns": self.columns,
            "rows": self.rows,
            "free_cells": self.free_cells,
            "occupied_cells": self.occupied_cells,
        }

    def document(self) -> dict[str, Any]:
        outputs = {"map_yaml": str(self.map_yaml), "image": str(self.image)}
        return document(
            "world export", {"world": world_input(self.world)}, outputs=outputs, **self.to_dict()
        )


def image_beside(map_yaml: Path) -> Path:
    """The PGM written with a map's YAML file: its name with the suffix .pgm."""
    if map_yaml.suffix.lower() not in YAML_SUFFIXES:
        raise BadInput(f"{map_yaml}: a map_server map is a .yaml file (its PGM goes beside it)")
    return map_yaml.with_suffix(".pgm")


def export_map(given: Path | WorldMap, map_yaml: Path) -> Exported:
    """Rasterise a world (a file, or one made here) at its cell size and write it as
    map_saver writes a map, its origin the world's (so that importing it gives back the
    world's frame)."""
    image = image_beside(map_yaml)
    if isinstance(given, Path):
        refuse_output_among_inputs(map_yaml, {"the world": given})
        refuse_output_among_inputs(image, {"the world": given})
    world = world_of(given)
    raster = rasterise(world)
    free = ~(raster.occupied | raster.outside)
    write_occupancy_map(map_yaml, image, free, raster.occupied, world.cell_m, world.origin_m)
    rows, columns = free.shape
    return Exported(
        given,
        map_yaml,
        image,
        world.cell_m,
        columns,
        rows,
        int(free.sum()),
        int(raster.occupied.sum()),
    )
