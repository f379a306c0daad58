"""FAM inference of many views in plain numpy, every view and corner at once: what
`core.fam_perception_kernel.infer_views` computes, kept for the tests that compare the two."""

from __future__ import annotations

import numpy as np

from tvl_cli.core.fam_firing import Firing
from tvl_cli.core.fuzzy import StackedPartitions


def infer_views_reference(
    rings: np.ndarray,
    ring_of_view: np.ndarray,
    rotation_of_view: np.ndarray,
    firing: tuple[np.ndarray, ...],
    lookup: np.ndarray,
    trajectory_at: np.ndarray,
    strength: np.ndarray,
    offset: np.ndarray,
    velocities: np.ndarray,
    experience: np.ndarray,
) -> None:
    """Fill velocities (V, J) m/s and experience (V, J), as perception.infer_views (which
    documents the arguments; strength and offset are not needed)."""
    sonars, interior, gap_start, gap_low, gap_width, strides, first_rows, counts = firing
    layout = Firing(
        sonars, StackedPartitions(interior, gap_start, gap_low, gap_width), strides, first_rows,
        counts,
    )  # fmt: skip
    count = rings.shape[1]
    rotated = (sonars[..., None] + rotation_of_view) % count  # (g, n, T, V)
    x = rings.take(ring_of_view * count + rotated).min(axis=0)  # (n, T, V) metres
    base, strength = layout.fire(x)
    stored = lookup.take(base + layout.corners[..., None], axis=1)  # (2 cols, C, T, V)
    average = np.einsum("mctn,ctn->mtn", stored, strength)  # (2 cols, T, V)
    average /= strength.sum(axis=0)
    table, column = np.nonzero(trajectory_at >= 0)
    order = np.argsort(trajectory_at[table, column])  # by trajectory
    table, column = table[order], column[order]
    columns = len(lookup) // 2
    velocities[...] = average[column, table].T
    experience[...] = average[columns + column, table].T
