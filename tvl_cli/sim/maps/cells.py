"""A text map's grid as arrays: its characters' code points, the outline between wall and
open cells as maximal straight runs, and whether the open cells round the start are
enclosed; each in numpy or a compiled loop, so that a scanned map of a million cells is
read in a second, not a minute of Python.

Rows count from the top, as the text is written; `OUTSIDE` marks the cells past the end of a
short line, which belong to no one.
"""

from __future__ import annotations

import numpy as np

OUTSIDE = 0xFFFF_FFFF  # no character has this code point


def char_codes(rows: tuple[str, ...]) -> np.ndarray:
    """(rows, columns) uint32 code points of the map's characters, OUTSIDE past a line's end."""
    columns = max((len(row) for row in rows), default=0)
    codes = np.full((len(rows), columns), OUTSIDE, dtype=np.uint32)
    for r, row in enumerate(rows):
        codes[r, : len(row)] = np.frombuffer(row.encode("utf-32-le"), dtype="<u4")
    return codes


def first_where(mask: np.ndarray) -> tuple[int, int] | None:
    """The (row, column) of the first True cell in reading order, or None."""
    found = np.flatnonzero(mask)
    return divmod(int(found[0]), mask.shape[1]) if len(found) else None


def outline_runs(wall: np.ndarray, open_cells: np.ndarray) -> np.ndarray:
    """The edges between wall cells and open cells, merged into maximal straight runs, each
    keeping the wall on its left: (n, 5) int64 rows of (axis, line, direction, first, end),
    sorted by axis (0 along x, 1 along y), line, direction (-1 before +1) and first.

    On axis 0 a run lies along y = line cells from the bottom, from x = first to x = end
    cells (direction +1: wall above it) or from end back to first (-1: wall below); on axis 1
    along x = line, from y = first to end (+1: wall on its left, open to its right) or back.
    Edges between two wall cells, or facing off the map, are never seen by the robot."""
    rows = wall.shape[0]
    padded = np.pad(open_cells, 1, constant_values=False)  # off the map: not open
    below = wall & padded[2:, 1:-1]  # open below: runs +x along y = rows - 1 - r
    above = wall & padded[:-2, 1:-1]  # open above: runs -x along y = rows - r
    right = wall & padded[1:-1, 2:]  # open right: runs +y along x = c + 1
    left = wall & padded[1:-1, :-2]  # open left: runs -y along x = c
    line = np.arange(rows)[:, None]
    runs = [
        _runs(below, 0, rows - 1 - line, 1),
        _runs(above, 0, rows - line, -1),
        # Along y the cells count up from the bottom: rows reversed, then each column a line.
        _runs(right[::-1].T, 1, np.arange(wall.shape[1])[:, None] + 1, 1),
        _runs(left[::-1].T, 1, np.arange(wall.shape[1])[:, None], -1),
    ]
    every = np.concatenate(runs)
    order = np.lexsort((every[:, 3], every[:, 2], every[:, 1], every[:, 0]))
    return every[order]


def _runs(mask: np.ndarray, axis: int, line: np.ndarray, direction: int) -> np.ndarray:
    """(n, 5) the runs of True along each row of mask, that row lying on line[row]."""
    steps = np.diff(np.pad(mask, ((0, 0), (1, 1))).astype(np.int8), axis=1)
    row, first = np.nonzero(steps == 1)
    _, end = np.nonzero(steps == -1)  # in the same reading order: each run's end
    lines = line.reshape(-1)[row]
    return np.stack(
        [np.full(len(row), axis), lines, np.full(len(row), direction), first, end], axis=1
    ).astype(np.int64)


def reaches_outside(
    open_cells: np.ndarray, outside: np.ndarray, start: tuple[int, int], sides: np.ndarray
) -> bool:
    """Whether the open cells joined to the start's (up, down, left and right, never between
    cells of different `sides`) touch a cell outside the map or off its edge: a compiled
    flood (sim.flood_kernel) over the start's side.

    sides (rows + 2, columns + 2): a number for each cell and the ring of cells round the
    map, equal for cells on the same side of every ring wall."""
    from tvl_cli.sim.flood_kernel import flood  # compiled: loaded on first use

    padded_open = np.pad(open_cells, 1, constant_values=False)
    padded_outside = np.pad(outside, 1, constant_values=True)  # off the map: outside
    row, column = start[0] + 1, start[1] + 1
    # A step never crosses a ring wall: only cells on the start's side take part.
    passable = (padded_open | padded_outside) & (sides == sides[row, column])
    reached = np.zeros_like(passable)
    flood(passable, row, column, reached)
    return bool((padded_outside & reached).any())
