"""The true clearance in plain numpy, all points against all obstacles at once: what
`clearance.clearances` computes, kept for the tests that compare the two."""

from __future__ import annotations

import numpy as np


def clearances_reference(
    points: np.ndarray,
    seg_start: np.ndarray,
    seg_delta: np.ndarray,
    seg_len: np.ndarray,
    discs: np.ndarray,
    rings: np.ndarray,
    body_radius_m: float,
    found: np.ndarray,
) -> None:
    """Fill found (p,) with metres, as clearance.clearances (which documents the
    arguments)."""
    px = points[:, 0:1]  # (p, 1) metres
    py = points[:, 1:2]
    nearest = np.full(len(points), np.inf)  # (p,) metres from the centre
    if len(seg_len):
        # Closest point on each segment: the projection clamped to the segment.
        (sx, sy), (ex, ey) = seg_start, seg_delta
        rx, ry = px - sx, py - sy  # (p, n) metres
        along = np.clip((rx * ex + ry * ey) / seg_len**2, 0.0, 1.0)
        gap = np.hypot(rx - along * ex, ry - along * ey)
        nearest = np.minimum(nearest, gap.min(axis=1))
    if len(discs):
        cx, cy, r = discs.T
        gap = np.hypot(px - cx, py - cy) - r  # (p, m)
        nearest = np.minimum(nearest, gap.min(axis=1))
    if len(rings):
        cx, cy, r = rings.T
        gap = r - np.hypot(px - cx, py - cy)  # (p, k)
        nearest = np.minimum(nearest, gap.min(axis=1))
    found[...] = np.maximum(nearest - body_radius_m, 0.0)
