"""The free space of an occupancy grid, as a body of some radius meets it: how far each free
cell's centre is from the nearest cell that is not free (scipy's exact distance transform),
the widest place to start, and the passages narrower than the body.

Arrays are (rows, columns), top row first, as maps are stored. A cell's clearance is the
distance from its centre to the nearest edge of a cell that is not free: the centres'
distance less half a cell, exact where the nearest wall lies straight along a row or column
and at most a fifth of a cell short where it lies diagonally. A body fits on a cell when its
clearance exceeds the radius; a passage is as wide as twice the clearance at its narrowest.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True, slots=True, eq=False)
class FreeSpace:
    """A grid's free cells and each one's clearance (metres; 0 on cells not free)."""

    free: np.ndarray  # (rows, columns) bool
    clearance_m: np.ndarray  # (rows, columns) metres
    cell_m: float

    def fits(self, radius_m: float) -> np.ndarray:
        """(rows, columns) bool: where a body of this radius stands clear of every wall."""
        return self.clearance_m > radius_m


@dataclass(frozen=True, slots=True)
class Passage:
    """A narrow way in: its width and its narrowest cell, and the cells reached through it."""

    width_m: float
    cell: tuple[int, int]  # (row, column)
    cut_off_cells: int  # cells a body fits on that only this passage leads to


def free_space(free: np.ndarray, cell_m: float) -> FreeSpace:
    """The clearance of every free cell of a (rows, columns) grid; past its edges, walls."""
    from scipy import ndimage  # imported when a map is: its import costs tenths of a second

    padded = np.pad(free, 1, constant_values=False)
    centres = ndimage.distance_transform_edt(padded, sampling=cell_m)[1:-1, 1:-1]
    clearance = np.where(free, np.maximum(centres - cell_m / 2.0, 0.0), 0.0)
    return FreeSpace(free, clearance, cell_m)


def widest_place(space: FreeSpace, radius_m: float) -> tuple[int, int] | None:
    """The cell of most clearance in the largest piece of floor a body of this radius can
    roam (cells joined up, down, left and right), the first in reading order of equals;
    None if the body fits nowhere."""
    from scipy import ndimage

    pieces, count = ndimage.label(space.fits(radius_m))
    if count == 0:
        return None
    largest = 1 + int(np.argmax(np.bincount(pieces.reshape(-1))[1:]))
    flat = int(np.argmax(np.where(pieces == largest, space.clearance_m, -1.0)))
    row, column = divmod(flat, space.free.shape[1])
    return row, column


def narrow_passages(space: FreeSpace, start: tuple[int, int], radius_m: float) -> list[Passage]:
    """The passages narrower than a body of this radius through which alone free floor it
    fits on is reached from the start, narrowest first.

    The widest way from the start to each free cell (the way whose narrowest point is
    widest) runs along the maximum spanning tree of the free cells, each step between
    neighbours as wide as the narrower of the two; scipy finds the tree, and one pass down
    it from the start carries each way's narrowest cell. A cell the body fits on whose
    widest way narrows below the body is cut off, by the passage at that narrowest cell."""
    from scipy.sparse.csgraph import breadth_first_order

    rows, columns = space.free.shape
    clearance = space.clearance_m.reshape(-1)
    tree = _widest_tree(space.free, clearance)
    origin = start[0] * columns + start[1]
    order, parent = breadth_first_order(tree, origin, directed=False)
    narrowest = np.full(rows * columns, -1, dtype=np.int64)  # each cell's way's narrowest cell
    narrowest[origin] = origin
    for cell in order[1:].tolist():
        above = narrowest[parent[cell]]
        narrowest[cell] = cell if clearance[cell] < clearance[above] else above
    reached = np.zeros(rows * columns, dtype=bool)
    reached[order] = True
    fits = space.fits(radius_m).reshape(-1)
    cut_off = reached & fits & (clearance[narrowest] <= radius_m)
    cells, counts = np.unique(narrowest[cut_off], return_counts=True)
    passages = [
        Passage(2.0 * float(clearance[cell]), divmod(int(cell), columns), int(count))
        for cell, count in zip(cells.tolist(), counts.tolist(), strict=True)
    ]
    return sorted(passages, key=lambda p: (p.width_m, p.cell))


def _widest_tree(free: np.ndarray, clearance: np.ndarray) -> Any:
    """The maximum spanning tree of the free cells, each joined to its right and lower
    neighbours by a step as wide as the narrower cell (a sparse matrix, flat indices)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import minimum_spanning_tree

    rows, columns = free.shape
    index = np.arange(rows * columns).reshape(rows, columns)
    pairs = [
        (index[:, :-1][free[:, :-1] & free[:, 1:]], 1),  # a cell and its right neighbour
        (index[:-1, :][free[:-1, :] & free[1:, :]], columns),  # and its lower neighbour
    ]
    a = np.concatenate([cells for cells, _ in pairs])
    b = np.concatenate([cells + step for cells, step in pairs])
    width = np.minimum(clearance[a], clearance[b])
    # The widest tree is the least one under weights that fall as the width grows (all above
    # zero: scipy leaves out edges of weight 0).
    weight = 1.0 + width.max(initial=0.0) - width
    graph = coo_matrix((weight, (a, b)), shape=(rows * columns, rows * columns))
    return minimum_spanning_tree(graph)
