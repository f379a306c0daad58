"""The true clearance: how far a body's edge is from the nearest obstacle, at many points or
at one (a run measures it every step). Bit for bit what `clearance_reference`
(tests/kernel_references/) computes.

Each point asks the walls of the grid's cells (sim.ring_kernel documents the grid) in
squares of cells growing round its own, and stops once the nearest wall found is nearer than
any cell not yet asked, or once every cell within `limit_m` has been asked."""

from __future__ import annotations

import math

from tvl_cli.core.numba_kernel import inlined, kernel

# Farther than any rounding of a distance in metres: a cell is passed over only when it lies
# beyond the nearest wall found by more than this.
_ROUNDING_M = 1e-6


@kernel
def clearances(
    points, seg_start, seg_delta, seg_len, grid, discs, rings, body_radius_m, limit_m, found,
    which,
):  # fmt: skip
    """Fill found (p,) with the metres from the edge of a body centred at each of points
    (p, 2) to the nearest obstacle: 0 where it touches or overlaps one, inf where none is
    within limit_m of the centre; and which (p,) with that obstacle, numbered segments first,
    then discs, then rings (-1: none). Segments as sim.geometry.StaticGeometry keeps them; discs
    (m, 3) and rings (k, 3) x, y, r metres."""
    for i in range(points.shape[0]):
        found[i], which[i] = clearance_at(
            points[i, 0], points[i, 1], seg_start, seg_delta, seg_len, grid, discs, rings,
            body_radius_m, limit_m,
        )  # fmt: skip


@inlined
def clearance_at(
    x, y, seg_start, seg_delta, seg_len, grid, discs, rings, body_radius_m, limit_m
):  # fmt: skip
    """(metres, obstacle): `clearances` at one point (x, y)."""
    n, m = seg_len.shape[0], discs.shape[0]
    nearest, obstacle = _nearest_segment(x, y, seg_start, seg_delta, seg_len, grid, limit_m)
    for j in range(discs.shape[0]):
        gap = math.hypot(x - discs[j, 0], y - discs[j, 1]) - discs[j, 2]
        if gap < nearest:
            nearest, obstacle = gap, n + j
    for j in range(rings.shape[0]):
        gap = rings[j, 2] - math.hypot(x - rings[j, 0], y - rings[j, 1])
        if gap < nearest:
            nearest, obstacle = gap, n + m + j
    if nearest > limit_m:
        nearest, obstacle = math.inf, -1
    return (nearest - body_radius_m if nearest > body_radius_m else 0.0), obstacle


@inlined
def _nearest_segment(x, y, seg_start, seg_delta, seg_len, grid, limit_m):
    """(metres, segment) of the segment nearest (x, y), the first numbered of equally near
    ones; (inf, -1) if none is nearer than every cell left unasked within limit_m."""
    x0, y0, cell_m, columns, rows, first, cell_walls, _ = grid
    nearest = math.inf
    obstacle = -1
    column = math.floor((x - x0) / cell_m)
    row = math.floor((y - y0) / cell_m)
    # The square of cells `ring` cells round the point's own covers the grid from `last` on.
    last = column
    for reach in (columns - 1 - column, row, rows - 1 - row):
        last = reach if reach > last else last
    for ring in range(last + 1):
        for r in range(row - ring, row + ring + 1):
            if r < 0 or r >= rows:
                continue
            # The square's edge: every column on its first and last rows, else the two ends.
            step = 1 if r == row - ring or r == row + ring else 2 * ring
            for c in range(column - ring, column + ring + 1, step):
                if c < 0 or c >= columns:
                    continue
                # A cell wholly farther than the nearest wall found, or than the limit, can
                # hold no nearer one.
                beyond = _box_gap(x - x0, c, cell_m) ** 2 + _box_gap(y - y0, r, cell_m) ** 2
                if beyond > (nearest + _ROUNDING_M) ** 2 or beyond > (limit_m + _ROUNDING_M) ** 2:
                    continue
                cell = r * columns + c
                for e in range(first[cell], first[cell + 1]):
                    j = cell_walls[e]
                    # Closest point on the segment: the projection clamped to the segment.
                    ex, ey = seg_delta[0, j], seg_delta[1, j]
                    rx, ry = x - seg_start[0, j], y - seg_start[1, j]
                    along = (rx * ex + ry * ey) / (seg_len[j] * seg_len[j])
                    along = 0.0 if along < 0.0 else (1.0 if along > 1.0 else along)
                    gap = math.hypot(rx - along * ex, ry - along * ey)
                    if gap < nearest or (gap == nearest and j < obstacle):
                        nearest, obstacle = gap, j
        # No wall yet unasked lies nearer than the square's edge.
        edge_m = x - (x0 + (column - ring) * cell_m)
        for side_m in (
            x0 + (column + ring + 1) * cell_m - x,
            y - (y0 + (row - ring) * cell_m),
            y0 + (row + ring + 1) * cell_m - y,
        ):
            edge_m = side_m if side_m < edge_m else edge_m
        if nearest < edge_m or edge_m > limit_m:
            break
    return nearest, obstacle


@kernel
def _box_gap(offset_m, index, cell_m):
    """Metres along one axis from a point this far from the grid's edge to cell `index`'s
    span on that axis (0 within it)."""
    low = index * cell_m
    if offset_m < low:
        return low - offset_m
    high = low + cell_m
    return offset_m - high if offset_m > high else 0.0
