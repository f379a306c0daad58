"""Training's rule updates in plain numpy, every exemplar and corner of a chunk at once: what
`core.fam_rule_updates_kernel.train_table` computes, kept for the tests that compare the two."""

from __future__ import annotations

import numpy as np

from tvl_cli.core.fam_firing import Firing
from tvl_cli.core.fuzzy import StackedPartitions


def train_table_reference(
    readings: np.ndarray,
    velocities_mps: np.ndarray,
    rows: np.ndarray,
    columns: np.ndarray,
    pass_ends: np.ndarray,
    pass_sonars: np.ndarray,
    partitions: tuple[np.ndarray, ...],
    strides: np.ndarray,
    corner_offsets: np.ndarray,
    high_inputs: int,
    chunk_rows: int,
    lookup: np.ndarray,
    first_row: int,
    table_columns: int,
    weighted_sum: np.ndarray,
    sums: np.ndarray,
    met: np.ndarray,
    upper: np.ndarray,
    lowest: np.ndarray,
    strength: np.ndarray,
    weighted: np.ndarray,
    change: np.ndarray,
) -> int:
    """How many entries were recomputed, listed in met[0] in increasing order with their
    absolute change in `change`, as rule_updates.train_table (which documents the
    arguments; this one needs no room to work in, nor to split the corners' strengths)."""
    count = len(readings) // len(velocities_mps)
    entries = len(weighted_sum)
    d_experience = np.zeros(entries)  # (R_t * traj_t,) this batch's sum of w
    d_weighted = np.zeros(entries)  # (R_t * traj_t,) its sum of w * v, m/s
    start = 0
    for sonars, end in zip(pass_sonars, pass_ends, strict=False):
        firing = Firing(
            sonars[..., None], StackedPartitions(*partitions), strides[:, None],
            np.zeros(1, dtype=np.intp), np.array([len(strides)]),
        )  # fmt: skip
        for chunk in range(start, end, chunk_rows):
            mine = slice(chunk, min(chunk + chunk_rows, end))
            # (n, 1, M) inputs, gathered straight from the row-major (N * 16,) readings
            x = readings.take(rows[mine] * count + firing.sonars[..., None]).min(axis=0)
            base, strength = firing.fire(x)
            base += columns[mine]
            index = (base + firing.corners[..., None]).ravel()  # (C * M,) entries
            d_experience += np.bincount(index, strength.ravel(), entries)
            strength *= velocities_mps[rows[mine]]
            d_weighted += np.bincount(index, strength.ravel(), entries)
        start = end
    touched = np.flatnonzero(d_experience > 0)
    rule, column = first_row + touched // table_columns, touched % table_columns
    experience_row = len(lookup) // 2 + column
    before = lookup[column, rule]
    lookup[experience_row, rule] += d_experience[touched]
    weighted_sum += d_weighted
    lookup[column, rule] = weighted_sum[touched] / lookup[experience_row, rule]
    met[0, : len(touched)] = touched
    change[: len(touched)] = np.abs(lookup[column, rule] - before)
    return len(touched)
