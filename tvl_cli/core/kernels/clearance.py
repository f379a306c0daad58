"""The true clearance: how far a body's edge is from the nearest obstacle, at many points or
at one (a run measures it every step). Bit for bit what `clearance_reference` computes."""

from __future__ import annotations

import math

from tvl_cli.core.kernels import kernel


@kernel
def clearances(
    points, seg_start, seg_delta, seg_len, discs, rings, body_radius_m, found, which
):  # fmt: skip
    """Fill found (p,) with the metres from the edge of a body centred at each of points
    (p, 2) to the nearest obstacle: 0 where it touches or overlaps one, inf with no
    obstacles; and which (p,) with that obstacle, numbered segments first, then discs, then
    rings (-1: none). Segments as sim.world.StaticGeometry keeps them; discs (m, 3) and
    rings (k, 3) x, y, r metres."""
    n, m = seg_len.shape[0], discs.shape[0]
    for i in range(points.shape[0]):
        x, y = points[i, 0], points[i, 1]
        nearest = math.inf  # metres from the centre
        obstacle = -1
        for j in range(seg_len.shape[0]):
            # Closest point on the segment: the projection clamped to the segment.
            ex, ey = seg_delta[0, j], seg_delta[1, j]
            rx, ry = x - seg_start[0, j], y - seg_start[1, j]
            along = (rx * ex + ry * ey) / (seg_len[j] * seg_len[j])
            along = 0.0 if along < 0.0 else (1.0 if along > 1.0 else along)
            gap = math.hypot(rx - along * ex, ry - along * ey)
            if gap < nearest:
                nearest, obstacle = gap, j
        for j in range(discs.shape[0]):
            gap = math.hypot(x - discs[j, 0], y - discs[j, 1]) - discs[j, 2]
            if gap < nearest:
                nearest, obstacle = gap, n + j
        for j in range(rings.shape[0]):
            gap = rings[j, 2] - math.hypot(x - rings[j, 0], y - rings[j, 1])
            if gap < nearest:
                nearest, obstacle = gap, n + m + j
        found[i] = nearest - body_radius_m if nearest > body_radius_m else 0.0
        which[i] = obstacle
