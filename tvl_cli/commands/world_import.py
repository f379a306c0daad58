"""`tvl world import`: a ROS map_server occupancy grid (YAML and image) -> a world file."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from tvl_cli.core.errors import BadInput
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.occupancy_map import OccupancyMap, read_occupancy_map
from tvl_cli.sim.maps.grid_world import GridPlace, GridWorld, grid_world
from tvl_cli.sim.worldheader import MAX_CELL_M, MIN_CELL_M
from tvl_cli.sim.worldmap import MAX_FILE_BYTES, parse_world


@dataclass(frozen=True, slots=True)
class ImportRequest:
    map_yaml: Path
    output: Path
    start: tuple[float, float, float]  # map-frame x, y (m) and heading (degrees, CCW from +x)
    name: str | None = None  # the world's name; the YAML file's stem by default
    force: bool = False  # replace an output that appeared while the world was made


@dataclass(frozen=True, slots=True)
class Imported:
    """What was written, in the terms of the map it came from."""

    map: OccupancyMap
    world: GridWorld
    free_cells: int

    def to_dict(self) -> dict[str, object]:
        place, (x, y, heading) = self.world.place, self.world.start
        return {
            "cell_m": place.cell_m,
            "columns": self.world.columns,
            "rows": self.world.rows,
            "free_cells": self.free_cells,
            # The map frame's coordinates of the world's origin (its bottom-left corner).
            "offset_m": [_tidy(place.left_x_m), _tidy(place.bottom_y_m)],
            "start": [_tidy(x), _tidy(y), math.degrees(heading)],
            "unknown_grey_free": self.map.unknown_grey_free,
        }


def _tidy(metres: float) -> float:
    """To the nanometre: 0.35, not the 0.35000000000000003 that summing cells gives."""
    return round(metres, 9)


def parse_start(text: str) -> tuple[float, float, float]:
    """'X,Y,HEADING_DEG': map-frame metres, and degrees counter-clockwise from +x."""
    try:
        x, y, heading = (float(part) for part in text.split(","))
    except ValueError:
        x = y = heading = math.nan
    if not all(math.isfinite(v) for v in (x, y, heading)):
        raise BadInput(f"--start {text!r}: expected X,Y,HEADING_DEG, e.g. 1.5,2.0,90")
    return x, y, heading


def import_map(request: ImportRequest) -> Imported:
    """Read the map, make its world, check it as `tvl world check` would, and write it."""
    occupancy = read_occupancy_map(request.map_yaml)
    meta = occupancy.meta
    where = meta.path
    if meta.origin_yaw_rad != 0.0:
        raise BadInput(
            f"{where}: origin yaw is {meta.origin_yaw_rad:g} rad; a world's walls run along "
            "its axes, so only a map with yaw 0 can be imported"
        )
    if not MIN_CELL_M <= meta.resolution_m <= MAX_CELL_M:
        raise BadInput(
            f"{where}: resolution {meta.resolution_m:g} m is outside a world's cell sizes "
            f"({MIN_CELL_M:g} to {MAX_CELL_M:g} m)"
        )
    if not occupancy.free.any():
        raise BadInput(f"{where}: the map has no free cell (under its free_thresh)")
    name = request.name if request.name is not None else where.stem
    if not name.strip() or name != name.strip() or not name.isprintable():
        raise BadInput(f"--name {name!r}: a world's name is one line of text")
    about = (
        f"imported from {where.name}: mode {meta.mode}, negate {int(meta.negate)}, "
        f"occupied_thresh {meta.occupied_thresh:g}, free_thresh {meta.free_thresh:g}",
        "cells not known to be free are walls",
    )
    place = GridPlace(meta.resolution_m, meta.origin_x_m, meta.origin_y_m)
    try:
        made = grid_world(occupancy.free, place, request.start, name, about)
    except ValueError as error:
        x, y, heading = request.start
        raise BadInput(f"--start {x:g},{y:g},{heading:g}: {error}") from None
    text = made.text
    size = len(text.encode("utf-8"))
    if size > MAX_FILE_BYTES:
        raise BadInput(
            f"{where}: its free floor spans {made.columns} x {made.rows} cells, a world file "
            f"of {size:,} bytes, over the {MAX_FILE_BYTES:,} a world may have"
        )
    parse_world(text, str(request.output))  # holds the file to `tvl world check` before writing
    with atomic_output(request.output, overwrite=request.force) as temporary:
        temporary.write_text(text, encoding="utf-8")
    return Imported(occupancy, made, int(occupancy.free.sum()))
