"""Flood fill: the cells of a grid joined to a start through open neighbours (up, down, left
and right), for the reachable floor of a world and the enclosure of a large map. What
`flood_reference` (tests/kernel_references/) computes, cell for cell."""

from __future__ import annotations

import numpy as np

from tvl_cli.core.numba_kernel import kernel


@kernel
def flood(open_cells, start_row, start_column, reached):
    """Set reached (rows, columns) True on every open cell joined to the start's (which is
    reached whether open or not) through open cells, each step to a neighbour up, down, left
    or right; the rest are left as they are (False)."""
    rows, columns = open_cells.shape
    stack = np.empty(rows * columns, dtype=np.int64)  # cells reached, not yet spread from
    stack[0] = start_row * columns + start_column
    reached[start_row, start_column] = True
    size = 1
    while size > 0:
        size -= 1
        row, column = divmod(stack[size], columns)
        for next_row, next_column in (
            (row - 1, column),
            (row + 1, column),
            (row, column - 1),
            (row, column + 1),
        ):
            if (
                0 <= next_row < rows
                and 0 <= next_column < columns
                and open_cells[next_row, next_column]
                and not reached[next_row, next_column]
            ):
                reached[next_row, next_column] = True
                stack[size] = next_row * columns + next_column
                size += 1
