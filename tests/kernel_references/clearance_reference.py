"""The true clearance in plain numpy, all points against all obstacles at once: what
`sim.clearance_kernel.clearances` computes, kept for the tests that compare the two."""

from __future__ import annotations

import numpy as np


def clearances_reference(
    points: np.ndarray,
    seg_start: np.ndarray,
    seg_delta: np.ndarray,
    seg_len: np.ndarray,
    grid: tuple[object, ...],
    discs: np.ndarray,
    rings: np.ndarray,
    body_radius_m: float,
    limit_m: float,
    found: np.ndarray,
    which: np.ndarray,
) -> None:
    """Fill found (p,) with metres and which (p,) with obstacles, as clearance.clearances
    (which documents the arguments; this asks every segment, and leaves the grid unused)."""
    px = points[:, 0:1]  # (p, 1) metres
    py = points[:, 1:2]
    gaps = [np.full((len(points), 1), np.inf)]  # (p, 1) no obstacle at all, then each kind
    if len(seg_len):
        # Closest point on each segment: the projection clamped to the segment.
        (sx, sy), (ex, ey) = seg_start, seg_delta
        rx, ry = px - sx, py - sy  # (p, n) metres
        along = np.clip((rx * ex + ry * ey) / seg_len**2, 0.0, 1.0)
        gaps.append(np.hypot(rx - along * ex, ry - along * ey))
    if len(discs):
        cx, cy, r = discs.T
        gaps.append(np.hypot(px - cx, py - cy) - r)  # (p, m)
    if len(rings):
        cx, cy, r = rings.T
        gaps.append(r - np.hypot(px - cx, py - cy))  # (p, k)
    every = np.concatenate(gaps, axis=1)  # (p, 1 + n + m + k) metres from the centre
    first = every.argmin(axis=1)  # (p,) the first of the nearest, as the kernel keeps it
    nearest = every[np.arange(len(points)), first]
    within = nearest <= limit_m
    found[...] = np.where(within, np.maximum(nearest - body_radius_m, 0.0), np.inf)
    which[...] = np.where(within, first - 1, -1)
