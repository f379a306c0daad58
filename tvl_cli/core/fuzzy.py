"""Fuzzification of ranges by Ruspini partitions of triangles with shoulder ends.

Between two neighbouring centres c_k < c_(k+1) only sets k and k+1 are non-zero, with degrees
1 - t and t where t = (x - c_k) / (c_(k+1) - c_k); below the first centre the first set has
degree 1, above the last centre the last set has. So a reading is fully described by the
lower set index k and the upper degree t, and at most two sets fire.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from tvl_cli.core.fam_config import Partition


@dataclass(frozen=True, slots=True, eq=False)
class StackedPartitions:
    """Several partitions applied side by side: row j of an input array uses partition j."""

    # (n, kmax - 2) inner centres c_1..c_(K-2) of each partition; NaN pads, as no reading
    # (not even +inf) compares >= NaN
    interior_m: np.ndarray
    gap_start: np.ndarray  # (n,) index of each partition's first gap in the flat gap arrays
    gap_low_m: np.ndarray  # (gaps,) lower centre of every gap, partitions one after another
    gap_width_m: np.ndarray  # (gaps,) width of every gap

    @classmethod
    def of(cls, partitions: Sequence[Partition]) -> StackedPartitions:
        centres = [np.asarray(p.centres_m, dtype=np.float64) for p in partitions]
        interior = np.full((len(centres), max(len(c) for c in centres) - 2), np.nan)
        for j, c in enumerate(centres):
            interior[j, : len(c) - 2] = c[1:-1]
        gaps = [len(c) - 1 for c in centres]
        return cls(
            interior,
            np.cumsum([0, *gaps[:-1]]).astype(np.intp),
            np.concatenate([c[:-1] for c in centres]),
            np.concatenate([np.diff(c) for c in centres]),
        )

    def fuzzify(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lower set index (n, N) intp and upper degree (n, N) in [0, 1] of readings (n, N).

        Row j of x is fuzzified by partition j. Readings are metres, finite or +inf (which
        sits in the last set).
        """
        # Counting the inner centres at or below x gives the gap x lies in, clamped to the
        # first and last gap, which is where the shoulders are.
        lower = (x[:, None, :] >= self.interior_m[:, :, None]).sum(axis=1)
        gap = lower + self.gap_start[:, None]
        upper = np.subtract(x, self.gap_low_m.take(gap))
        upper /= self.gap_width_m.take(gap)
        np.maximum(upper, 0.0, out=upper)  # the shoulders
        np.minimum(upper, 1.0, out=upper)
        return lower, upper


def memberships(partition: Partition, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower set index and upper degree of readings x in metres, each shaped as x."""
    x = np.asarray(x, dtype=np.float64)
    lower, upper = StackedPartitions.of((partition,)).fuzzify(x.reshape(1, -1))
    return lower.reshape(x.shape), upper.reshape(x.shape)
