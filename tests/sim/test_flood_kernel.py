"""The compiled flood fill reaches, cell for cell, what the plain one does, on random grids
from every start: open and not, at the edges and inside."""

from __future__ import annotations

import numpy as np
import pytest
from kernel_references.flood_reference import flood_reference

from tvl_cli.sim.flood_kernel import flood


@pytest.mark.parametrize("seed", range(30))
def test_the_kernel_floods_as_the_reference(seed: int) -> None:
    rng = np.random.default_rng(seed)
    rows, columns = rng.integers(1, 60, size=2)
    open_cells = rng.random((rows, columns)) < rng.uniform(0.3, 0.8)
    start = (int(rng.integers(rows)), int(rng.integers(columns)))
    compiled = np.zeros((rows, columns), dtype=bool)
    reference = np.zeros((rows, columns), dtype=bool)
    flood(open_cells, *start, compiled)
    flood_reference(open_cells, *start, reference)
    np.testing.assert_array_equal(compiled, reference)
    assert compiled[start]
    assert (compiled & ~open_cells).sum() <= 1  # only the start may be closed


def test_a_flood_stays_within_walls() -> None:
    open_cells = np.array([[1, 1, 0, 1], [1, 0, 0, 1], [1, 1, 1, 1]], dtype=bool)
    open_cells[1, 3] = False
    reached = np.zeros_like(open_cells)
    flood(open_cells, 0, 0, reached)
    assert reached.tolist() == [
        [True, True, False, False],
        [True, False, False, False],
        [True, True, True, True],
    ]
