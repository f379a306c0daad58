"""The true clearance: how far a body's edge is from the nearest obstacle, at many points or
at one (a run measures it every step). Bit for bit what `clearance_reference` computes."""

from __future__ import annotations

import math

import numpy as np

from tvl_cli.core.kernels import kernel


@kernel
def clearances(points, seg_start, seg_delta, seg_len, discs, rings, body_radius_m):
    """(p,) metres from the edge of a body centred at each of points (p, 2) to the nearest
    obstacle; 0 where it touches or overlaps one, inf with no obstacles. Segments as
    sim.world.StaticGeometry keeps them; discs (m, 3) and rings (k, 3) x, y, r metres."""
    found = np.empty(points.shape[0])  # (p,) metres
    for i in range(points.shape[0]):
        found[i] = clearance(
            points[i, 0], points[i, 1], seg_start, seg_delta, seg_len, discs, rings, body_radius_m
        )
    return found


@kernel
def clearance(x, y, seg_start, seg_delta, seg_len, discs, rings, body_radius_m):
    """Metres from the edge of a body centred at (x, y) to the nearest obstacle, as
    `clearances`."""
    nearest = math.inf  # metres from the centre
    for j in range(seg_len.shape[0]):
        # Closest point on the segment: the projection clamped to the segment.
        ex, ey = seg_delta[0, j], seg_delta[1, j]
        rx, ry = x - seg_start[0, j], y - seg_start[1, j]
        along = min(max((rx * ex + ry * ey) / (seg_len[j] * seg_len[j]), 0.0), 1.0)
        nearest = min(nearest, math.hypot(rx - along * ex, ry - along * ey))
    for j in range(discs.shape[0]):
        nearest = min(nearest, math.hypot(x - discs[j, 0], y - discs[j, 1]) - discs[j, 2])
    for j in range(rings.shape[0]):
        nearest = min(nearest, rings[j, 2] - math.hypot(x - rings[j, 0], y - rings[j, 1]))
    return max(nearest - body_radius_m, 0.0)
