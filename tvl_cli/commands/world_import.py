"""`tvl world import`: a ROS map_server occupancy grid (YAML and image) -> a world file in the
map's own frame, cropped and coarsened if asked, the robot's start chosen if not given."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.core.errors import BadInput
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.json_documents import document, input_file
from tvl_cli.io.occupancy_map import OccupancyMap, read_occupancy_map
from tvl_cli.io.paths import refuse_output_among_inputs
from tvl_cli.sim.maps.cells import outline_runs
from tvl_cli.sim.maps.free_space import (
    FreeSpace,
    Passage,
    free_space,
    narrow_passages,
    widest_place,
)
from tvl_cli.sim.maps.grid_world import (
    GridPlace,
    GridWorld,
    body_touches,
    floor_of,
    grid_world,
    metres,
)
from tvl_cli.sim.maps.resample import coarsen, crop
from tvl_cli.sim.world_budget import max_file_bytes, max_image_pixels, over_budget
from tvl_cli.sim.worldheader import MAX_CELL_M, MAX_HEADING_DEG, MIN_CELL_M
from tvl_cli.sim.worldmap import parse_world

Box = tuple[float, float, float, float]  # map-frame x0, y0, x1, y1 in metres


@dataclass(frozen=True, slots=True)
class ImportRequest:
    map_yaml: Path
    output: Path
    start: tuple[float, float, float] | None = None  # map-frame x, y (m), heading (degrees
    # CCW from +x); None: the widest free place, facing +x
    name: str | None = None  # the world's name; the YAML file's stem by default
    cell_m: float | None = None  # coarser cells than the map's (`--cell`); None: the map's
    crop: Box | None = None  # the part of the map to keep (`--crop`); None: all of it
    force: bool = False  # replace an output that appeared while the world was made
    robot: RobotConfig = DEFAULT_ROBOT  # the robot the start and the passages are judged for


@dataclass(frozen=True, slots=True)
class NarrowPassage:
    """A passage narrower than the robot, in the map's frame, and the floor beyond it that
    the robot would fit on."""

    width_m: float
    x_m: float  # its narrowest cell's centre
    y_m: float
    beyond_m2: float


@dataclass(frozen=True, slots=True)
class Imported:
    """What was written, in the map's frame (which is the world's)."""

    request: ImportRequest
    map: OccupancyMap
    world: GridWorld
    free_cells: int  # in the world's grid
    start_chosen: bool  # the start was chosen here, not given
    start_clearance_m: float  # from the body's centre to the nearest wall cell's edge
    # Narrower than the robot, narrowest first, each leading to at least the robot's own
    # footprint of floor: a crack into a pocket smaller than that is noise of the scan.
    passages: list[NarrowPassage] = field(default_factory=list)

    def to_dict(self) -> dict[str, object]:
        place = self.world.place
        x, y, heading = self.world.start
        return {
            "cell_m": place.cell_m,
            "columns": self.world.columns,
            "rows": self.world.rows,
            "free_cells": self.free_cells,
            # The map frame's coordinates of the world's bottom-left corner.
            "origin_m": [place.left_x_m, place.bottom_y_m],
            "start": [x, y, heading],
            "start_chosen": self.start_chosen,
            "narrow_passages": [asdict(p) for p in self.passages],
            "unknown_grey_free": self.map.unknown_grey_free,
        }

    def document(self) -> dict[str, Any]:
        r = self.request
        inputs = {
            "map_yaml": input_file(r.map_yaml),
            "image": input_file(self.map.meta.image),
            "start": None if r.start is None else list(r.start),
            "cell_m": r.cell_m,
            "crop_m": None if r.crop is None else list(r.crop),
            "name": r.name,
        }
        return document("world import", inputs, outputs={"world": str(r.output)}, **self.to_dict())


def parse_start(text: str) -> tuple[float, float, float]:
    """'X,Y,HEADING_DEG': map-frame metres, and degrees counter-clockwise from +x."""
    try:
        x, y, heading = (float(part) for part in text.split(","))
    except ValueError:
        x = y = heading = math.nan
    if not all(math.isfinite(v) for v in (x, y, heading)):
        raise BadInput(f"--start {text!r}: expected X,Y,HEADING_DEG, e.g. 1.5,2.0,90")
    if abs(heading) > MAX_HEADING_DEG:
        raise BadInput(
            f"--start {text!r}: heading {heading:g}° is beyond a turn "
            f"(from {-MAX_HEADING_DEG:g} to {MAX_HEADING_DEG:g})"
        )
    return x, y, heading


def parse_box(text: str) -> Box:
    """--crop 'X0,Y0,X1,Y1': the map-frame rectangle to keep, metres, X0 < X1 and Y0 < Y1."""
    try:
        x0, y0, x1, y1 = (float(part) for part in text.split(","))
    except ValueError:
        x0 = y0 = x1 = y1 = math.nan
    if not (all(math.isfinite(v) for v in (x0, y0, x1, y1)) and x0 < x1 and y0 < y1):
        raise BadInput(f"--crop {text!r}: expected X0,Y0,X1,Y1 with X0 < X1, Y0 < Y1, metres")
    return x0, y0, x1, y1


def import_map(request: ImportRequest) -> Imported:
    """Read the map, make its world, check it as `tvl world check` would, and write it."""
    refuse_output_among_inputs(request.output, {"MAP.yaml": request.map_yaml})
    occupancy = read_occupancy_map(request.map_yaml, max_image_pixels())
    refuse_output_among_inputs(request.output, {"the map's image": occupancy.meta.image})
    floor, place = floor_of(*_grid(occupancy, request))  # the world's grid
    robot = request.robot
    space = free_space(floor, place.cell_m)
    start, chosen = _start(request, space, place, robot.radius_m)
    made = grid_world(floor, place, start, _name(request), _comments(occupancy, request))
    _refuse_too_large(made, occupancy.meta.path)
    parse_world(made.text, str(request.output))  # held to `tvl world check` before writing
    start_cell = place.cell(made.rows, start[0], start[1])
    passages = _in_map_frame(narrow_passages(space, start_cell, robot.radius_m), made, robot)
    with atomic_output(request.output, overwrite=request.force) as temporary:
        temporary.write_text(made.text, encoding="utf-8")
    clearance = float(space.clearance_m[start_cell])
    return Imported(request, occupancy, made, int(floor.sum()), chosen, clearance, passages)


def _grid(occupancy: OccupancyMap, request: ImportRequest) -> tuple[np.ndarray, GridPlace]:
    """The map's free cells, cropped and coarsened as asked, and where they lie."""
    meta = occupancy.meta
    where = meta.path
    if meta.origin_yaw_rad != 0.0:
        raise BadInput(
            f"{where}: origin yaw is {meta.origin_yaw_rad:g} rad; a world's walls run along "
            "its axes, so only a map with yaw 0 can be imported"
        )
    free, place = occupancy.free, GridPlace(meta.resolution_m, meta.origin_x_m, meta.origin_y_m)
    if request.crop is not None:
        try:
            free, place = crop(free, place, request.crop)
        except ValueError as error:
            box = ",".join(f"{v:g}" for v in request.crop)
            raise BadInput(f"--crop {box}: {error} ({_extent(occupancy, place)})") from None
    cell_m = meta.resolution_m if request.cell_m is None else request.cell_m
    if request.cell_m is not None and not meta.resolution_m <= cell_m <= MAX_CELL_M:
        raise BadInput(
            f"--cell {cell_m:g}: cells are from the map's resolution, {meta.resolution_m:g} m, "
            f"to {MAX_CELL_M:g} m"
        )
    if not MIN_CELL_M <= cell_m <= MAX_CELL_M:
        raise BadInput(
            f"{where}: resolution {cell_m:g} m is outside a world's cell sizes "
            f"({MIN_CELL_M:g} to {MAX_CELL_M:g} m); give --cell"
        )
    if cell_m != meta.resolution_m:
        free, place = coarsen(free, place, cell_m)
    if not free.any():
        raise BadInput(f"{where}: the map has no free cell (under its free_thresh) to import")
    return free, place


def _start(
    request: ImportRequest, space: FreeSpace, place: GridPlace, radius_m: float
) -> tuple[tuple[float, float, float], bool]:
    """The start asked for, checked, or the widest free place facing +x; and whether it
    was chosen here."""
    rows = space.free.shape[0]
    widest = _widest(space, place, radius_m)
    if request.start is None:
        if widest is None:
            raise BadInput(
                f"{request.map_yaml}: no free place is wide enough for the robot (a disc of "
                f"radius {radius_m:g} m); the widest clearance is "
                f"{float(space.clearance_m.max()):.3g} m"
            )
        return (*widest, 0.0), True
    x, y, heading = request.start
    suggestion = (
        f"; the widest free place is x {widest[0]:g} y {widest[1]:g} "
        f"(--start {widest[0]:g},{widest[1]:g},{heading:g})"
        if widest is not None
        else ""
    )
    asked = f"--start {x:g},{y:g},{heading:g}"
    columns = space.free.shape[1]
    inside = (
        place.left_x_m <= x < place.left_x_m + columns * place.cell_m
        and place.bottom_y_m <= y < place.bottom_y_m + rows * place.cell_m
    )
    if not inside or not space.free[place.cell(rows, x, y)]:
        raise BadInput(f"{asked}: x {x:g} y {y:g} is not on the map's free floor{suggestion}")
    touched = body_touches(space.free, place, x, y, radius_m)
    if touched is not None:
        raise BadInput(
            f"{asked}: the robot (a disc of radius {radius_m:g} m) would touch the wall cell "
            f"at x {touched[0]:g} y {touched[1]:g}{suggestion}"
        )
    return (x, y, heading), False


def _widest(space: FreeSpace, place: GridPlace, radius_m: float) -> tuple[float, float] | None:
    """The map-frame centre of the widest free place a robot of `radius_m` can roam, or
    None."""
    cell = widest_place(space, radius_m)
    return None if cell is None else place.centre(space.free.shape[0], *cell)


def _in_map_frame(
    passages: list[Passage], made: GridWorld, robot: RobotConfig
) -> list[NarrowPassage]:
    """The passages that lead to at least the robot's footprint of floor, placed in the
    map's frame."""
    cell_area_m2 = made.place.cell_m**2
    footprint_m2 = math.pi * robot.radius_m**2
    return [
        NarrowPassage(
            metres(p.width_m),
            *made.place.centre(made.rows, *p.cell),
            round(p.cut_off_cells * cell_area_m2, 6),
        )
        for p in passages
        if p.cut_off_cells * cell_area_m2 >= footprint_m2
    ]


def _name(request: ImportRequest) -> str:
    name = request.name if request.name is not None else request.map_yaml.stem
    if not name.strip() or name != name.strip() or not name.isprintable():
        raise BadInput(f"--name {name!r}: a world's name is one line of text")
    return name


def _comments(occupancy: OccupancyMap, request: ImportRequest) -> tuple[str, ...]:
    """What the world was made from, for a reader of its file."""
    meta = occupancy.meta
    lines = [
        f"imported from {meta.path.name}: mode {meta.mode}, negate {int(meta.negate)}, "
        f"occupied_thresh {meta.occupied_thresh:g}, free_thresh {meta.free_thresh:g}",
        "cells not known to be free are walls; coordinates are the map's",
    ]
    if request.crop is not None:
        x0, y0, x1, y1 = request.crop
        lines.append(f"cropped to x {x0:g}..{x1:g} y {y0:g}..{y1:g} m")
    if request.cell_m is not None and request.cell_m != meta.resolution_m:
        lines.append(
            f"coarsened from {meta.resolution_m:g} m cells: a cell is free only where every "
            "map cell under it is"
        )
    return tuple(lines)


def _refuse_too_large(made: GridWorld, map_yaml: Path) -> None:
    """A world this machine cannot simulate is refused before it is written, naming the
    options that make it smaller."""
    size = len(made.text.encode("utf-8"))
    wall = ~made.floor
    too_large = over_budget(made.floor.size, len(outline_runs(wall, made.floor)))
    if size > max_file_bytes():
        too_large = f"a world file of {size:,} bytes, over the {max_file_bytes():,} it can read"
    if too_large is not None:
        raise BadInput(
            f"{map_yaml}: its free floor spans {made.columns} x {made.rows} cells: "
            f"{too_large}; coarsen it (--cell) or crop it (--crop)"
        )


def _extent(occupancy: OccupancyMap, place: GridPlace) -> str:
    """The map's extent in its frame, in words."""
    rows, columns = occupancy.free.shape
    x0, y0 = place.left_x_m, place.bottom_y_m
    x1, y1 = x0 + columns * place.cell_m, y0 + rows * place.cell_m
    return f"the map is x {x0:g}..{x1:g} y {y0:g}..{y1:g} m"
