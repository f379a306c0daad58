"""A world's solids drawn on its own cells: walls as written, and every pillar, disc, thin and
thick wall and ring on each cell it covers or passes through, and no other."""

from __future__ import annotations

import numpy as np

from tvl_cli.sim.maps.raster import rasterise
from tvl_cli.sim.worldmap import parse_world

# Inner cells x 1 to 6, y 1 to 5 m; the start in the bottom-right corner, out of the way.
ROOM = "\n".join(["#######", "#.....#", "#.....#", "#.....#", "#....>#", "#######"])


def occupied(header: str, grid: str = ROOM) -> np.ndarray:
    """The occupied cells of a 7 x 6 room of 1 m cells with the header's solids."""
    return rasterise(parse_world(f"cell: 1\n{header}\n{grid}\n", "test")).occupied


def inside(cells: np.ndarray) -> list[str]:
    """The room's inner cells, top row first, # where occupied."""
    return ["".join("#" if c else "." for c in row) for row in cells[1:-1, 1:-1]]


def test_the_grid_walls_are_the_maps_hashes() -> None:
    cells = occupied("")
    assert cells[[0, -1], :].all() and cells[:, [0, -1]].all()
    assert inside(cells) == ["....."] * 4


def test_a_pillar_fills_its_own_cell_only() -> None:
    assert inside(occupied("", ROOM.replace("#.....#\n#....>", "#.o...#\n#....>"))) == [
        ".....",
        ".....",
        ".#...",
        ".....",
    ]


def test_a_disc_fills_every_cell_it_covers_part_of() -> None:
    # Centred on the corner of four cells, radius 0.6: those four, not their neighbours.
    assert inside(occupied("disc: 3 3 0.6")) == [".....", ".##..", ".##..", "....."]


def test_a_thin_wall_along_a_cell_line_fills_the_cells_on_both_sides() -> None:
    assert inside(occupied("wall: 2 3 4 3")) == [".....", ".##..", ".##..", "....."]


def test_a_slanted_thin_wall_fills_the_cells_it_crosses_not_those_it_touches() -> None:
    # Through the corners (2, 2) and (3, 3): three cells, and none of those meeting there.
    assert inside(occupied("wall: 1.5 1.5 3.5 3.5")) == [".....", "..#..", ".#...", "#...."]


def test_a_thick_wall_fills_the_cells_its_rectangle_covers_not_those_it_touches() -> None:
    # A 1 m thick wall from x 2 to 4 along y = 2.5: the rectangle 2..4 x 2..3.
    assert inside(occupied("wall: 2 2.5 4 2.5 1")) == [".....", ".....", ".##..", "....."]


def test_a_ring_fills_the_cells_it_passes_through() -> None:
    # Reaching x 1.6 to 5.4 and y 1.1 to 4.9: the cells round the edge, none inside.
    assert inside(occupied("ring: 3.5 3 1.9")) == ["#####", "#...#", "#...#", "#####"]


def test_cells_past_a_short_lines_end_are_outside() -> None:
    raster = rasterise(parse_world("cell: 1\n#####\n#.>.#\n#####\n###\n", "short"))
    assert raster.outside[3].tolist() == [False, False, False, True, True]
    assert not raster.occupied[3, 3:].any()
