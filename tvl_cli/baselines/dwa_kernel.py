"""The DWA's free distances: how far each candidate arc can be followed before the body
comes too near an obstacle, compiled, with the clearances asked along each arc as it is
walked. `free_distances_reference` (tests/kernel_references/) computes the same from every
point's clearance, bit for bit, as the tests hold the kernel to.

Each arc is sampled at arc lengths s_m (K,). Too near is within the margin or, for a robot
already that near, nearer than it is now (so it may still drive away or along the
obstacle, never closer): that is what is *allowed*, and a point's *spare* clearance is its
clearance less that. An obstacle's distance changes by no more than the distance moved, so
from a point with spare clearance c at s the body is free until at least s + c: the first
point too near bounds the free distance from above, the point before it (the start
standing in before the first) from below, and the lower bound is kept. An arc free to its
end gives s_m[-1].

The same bound lets a point vouch for every later point of its arc within its spare
clearance of it: none of them can be too near. The walk asks a point, passes over the points it
vouches for, and asks the next; it stops at the first point too near. A query looks for
obstacles only `walk_m` from the body's edge (farther ones vouch for no more than that);
the point before the first too near one is asked again with `read_m`, where
free_distances reads clearances (dwa_window.clearance_read_m), so that its spare clearance
is exactly what the free distance adds.
"""

from __future__ import annotations

import math

from tvl_cli.core.numba_kernel import kernel
from tvl_cli.sim.clearance_kernel import clearance_at

# Far above the rounding of a distance in metres: a point is vouched for only when it lies
# this much inside the spare clearance, never on its edge.
_ROUNDING_M = 1e-9


@kernel
def walked_free_distances(
    points, s_m, allowed_m, start_spare_m, seg_start, seg_delta, seg_len, grid, discs, rings,
    body_radius_m, read_m, walk_m, free,
):  # fmt: skip
    """Fill free (N,) with the metres each arc of points (N, K, 2), sampled at arc lengths
    s_m (K,), can be followed, a clearance below allowed_m being too near and the start's
    spare clearance start_spare_m. Obstacles as sim.clearance_kernel.clearances takes them;
    read_m and walk_m metres from the body's edge, as above."""
    arcs, samples = points.shape[0], points.shape[1]
    r = body_radius_m
    for n in range(arcs):
        first = samples  # the first point too near; none: the arc is free to its end
        k = 0
        while k < samples:
            x, y = points[n, k, 0], points[n, k, 1]
            clearance, _ = clearance_at(
                x, y, seg_start, seg_delta, seg_len, grid, discs, rings, r, r + walk_m
            )  # fmt: skip
            if clearance < allowed_m:
                first = k
                break
            spare = (clearance if clearance < walk_m else walk_m) - allowed_m - _ROUNDING_M
            k += 1
            while k < samples and math.hypot(points[n, k, 0] - x, points[n, k, 1] - y) <= spare:
                k += 1
        if first == samples:
            # Every point has room to spare: the end bounds it (the last point's reach,
            # s_m[-1] plus its spare clearance, is no shorter).
            free[n] = s_m[samples - 1]
            continue
        s_before, spare_before = 0.0, start_spare_m
        if first > 0:
            s_before = s_m[first - 1]
            before, _ = clearance_at(
                points[n, first - 1, 0], points[n, first - 1, 1], seg_start, seg_delta,
                seg_len, grid, discs, rings, r, r + read_m,
            )  # fmt: skip
            spare_before = before - allowed_m
        reach = s_before + spare_before
        free[n] = reach if reach < s_m[first] else s_m[first]
