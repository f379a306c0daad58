"""A text map's grid as arrays: the compiled flood that asks a large map whether it is open
finds a way off the map exactly where the flood cell by cell does, with and without ring
walls."""

from __future__ import annotations

import numpy as np
import pytest

from tvl_cli.sim.maps.cells import OUTSIDE, char_codes, reaches_outside
from tvl_cli.sim.maps.text_grid import MapGrid, first_escape, ring_sides


def random_map(seed: int) -> tuple[MapGrid, tuple[int, int]]:
    """A 30 x 40 map of random walls, some rows cut short, and an open start cell."""
    rng = np.random.default_rng(seed)
    cells = np.where(rng.random((30, 40)) < rng.uniform(0.2, 0.5), "#", ".")
    if seed % 2:  # enclosed by a border
        cells[[0, -1], :] = "#"
        cells[:, [0, -1]] = "#"
    start = (int(rng.integers(1, 29)), int(rng.integers(1, 39)))
    cells[start] = ">"
    rows = ["".join(row) for row in cells]
    short = int(rng.integers(0, 30))
    rows[short] = rows[short][: int(rng.integers(5, 40))]
    return MapGrid(tuple(rows), tuple(range(1, 31)), 0.25), start


@pytest.mark.parametrize("rings", [(), ((5.0, 3.75, 2.5),), ((2.0, 2.0, 1.0), (8, 6, 4.0))])
@pytest.mark.parametrize("seed", range(40))
def test_the_compiled_flood_finds_a_way_off_the_map_as_the_flood_cell_by_cell(seed, rings) -> None:
    grid, start = random_map(seed)
    codes = char_codes(grid.rows)
    outside = codes == OUTSIDE
    open_cells = ~(outside | (codes == ord("#")))
    found = reaches_outside(open_cells, outside, start, ring_sides(grid, codes, rings))
    assert found == (first_escape(grid, *start, rings) is not None)
