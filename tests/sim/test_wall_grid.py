"""The wall grid lists each wall once in every cell it passes through, cell by cell and in
wall order within a cell."""

from __future__ import annotations

import numpy as np
import pytest

from tvl_cli.sim.geometry import geometry_of
from tvl_cli.sim.wall_grid import _sorted_unique


@pytest.mark.parametrize("count", [0, 1, 7, 5000])
def test_sorted_unique_is_numpys_unique(count: int) -> None:
    values = np.random.default_rng(count).integers(0, 1 + count // 3, count).astype(np.int64)
    assert _sorted_unique(values).tobytes() == np.unique(values).tobytes()


def test_a_crowded_grid_lists_each_wall_once_a_cell_in_order() -> None:
    # Overlapping patches, as the echo memory keeps them: enough to be bucketed by cell.
    rng = np.random.default_rng(1)
    centres = np.repeat(rng.uniform(0.0, 4.0, (50, 2)), 8, axis=0)
    across = rng.normal(0.0, 0.3, (400, 2))
    grid = geometry_of(np.hstack([centres - across, centres + across])).grid
    assert grid.columns * grid.rows > 1
    for cell in range(grid.columns * grid.rows):
        walls = grid.walls[grid.first[cell] : grid.first[cell + 1]]
        assert (np.diff(walls) > 0).all()  # increasing: each once, in order
    assert len(np.unique(grid.walls)) == 400  # every wall in some cell
