"""Flood fill in plain Python: what `sim.flood_kernel.flood` computes, kept for the tests that
compare the two. Same arguments, same result."""

from __future__ import annotations

from collections import deque

import numpy as np


def flood_reference(
    open_cells: np.ndarray, start_row: int, start_column: int, reached: np.ndarray
) -> None:
    """As flood.flood (which documents the arguments), breadth first."""
    rows, columns = open_cells.shape
    reached[start_row, start_column] = True
    queue = deque([(start_row, start_column)])
    while queue:
        row, column = queue.popleft()
        for r, c in ((row - 1, column), (row + 1, column), (row, column - 1), (row, column + 1)):
            if 0 <= r < rows and 0 <= c < columns and open_cells[r, c] and not reached[r, c]:
                reached[r, c] = True
                queue.append((r, c))
