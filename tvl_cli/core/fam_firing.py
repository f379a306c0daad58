"""How the rules of FAM tables fire: the corner layout perception fires every table with at
once (Firing), and the one training fires each table with alone, beside the room its sums
take (TableTraining)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from tvl_cli.core.fam_config import FamTable, Partition
from tvl_cli.core.fuzzy import StackedPartitions
from tvl_cli.core.robot_config import mirror_sonar

# Training sums this many corners (exemplars x 2^n) apart before adding them to a batch's sums:
# the grouping decides the rounding, so it stays as FAMs were always trained.
TRAIN_CHUNK_CORNERS = 2**18

# An input that always sits fully in its upper set, with stride 0: padding a table with it
# leaves its rules and strengths unchanged (the lower corners get strength 0), so tables with
# fewer inputs can be fired in one array with the widest.
_PADDING = Partition(("pad-lower", "pad-upper"), (-2.0, -1.0))


def _strides(shape: tuple[int, ...]) -> np.ndarray:
    """Flat-index step of each axis of a C-order array of this shape."""
    return np.array([int(np.prod(shape[k + 1 :])) for k in range(len(shape))], dtype=np.intp)


@dataclass(frozen=True, slots=True, eq=False)
class Firing:
    """Fires T tables side by side, padded to the same number n of inputs, so C = 2^n corners.

    Arrays end with the tables, so that firing N readings broadcasts over a last axis.
    """

    sonars: np.ndarray  # (g, n, T) ring indices; an input is the minimum over its g readings
    partitions: StackedPartitions  # the n * T partitions, input by input
    strides: np.ndarray  # (n, T) index step of each input's set, times the row scale
    first_rows: np.ndarray  # (T,) each table's first rule, times the row scale
    input_counts: np.ndarray  # (T,) each table's own inputs; the rest pad it
    # (C, T) index offset of each corner from the lowest, plus the first row: corner c takes
    # the upper set of input k when bit (n - 1 - k) of c is set, the order in which fire()
    # builds its strengths.
    corners: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        inputs = len(self.strides)
        bits = (np.arange(2**inputs)[:, None] >> np.arange(inputs - 1, -1, -1)) & 1  # (C, n)
        object.__setattr__(self, "corners", bits @ self.strides + self.first_rows)

    @classmethod
    def of(
        cls, tables: Sequence[FamTable], first_rows: Sequence[int], inputs: int, scale: int = 1
    ) -> Firing:
        groups = max(len(i.sonars) for t in tables for i in t.inputs)
        sonars = np.zeros((groups, inputs, len(tables)), dtype=np.intp)
        strides = np.zeros((inputs, len(tables)), dtype=np.intp)
        partitions = []
        for k in range(inputs):
            for t, table in enumerate(tables):
                if k < len(table.inputs):
                    group = table.inputs[k].sonars
                    # Repeating a sonar pads the group without changing its minimum.
                    sonars[:, k, t] = group + (group[0],) * (groups - len(group))
                    strides[k, t] = _strides(table.shape)[k] * scale
                    partitions.append(table.inputs[k].partition)
                else:
                    partitions.append(_PADDING)
        return cls(
            sonars,
            StackedPartitions.of(partitions),
            strides,
            np.asarray(first_rows, dtype=np.intp) * scale,
            np.array([len(t.inputs) for t in tables], dtype=np.intp),
        )

    def mirrored(self) -> Firing:
        """The same firing of the mirror image of the ring (Si <-> S(16-i))."""
        return replace(self, sonars=np.vectorize(mirror_sonar, otypes=[np.intp])(self.sonars))

    def kernel_inputs(self) -> tuple[np.ndarray, ...]:
        """The arrays the compiled FAM kernels fire with (core.fam_perception_kernel)."""
        p = self.partitions
        return (
            self.sonars, p.interior_m, p.gap_start, p.gap_low_m, p.gap_width_m, self.strides,
            self.first_rows, self.input_counts,
        )  # fmt: skip

    def fire(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lowest corner index (T, N) and corner strengths (C, T, N) of inputs x (n, T, N) m.

        Corner c's index is the lowest index plus corners[c].
        """
        inputs, tables, count = x.shape
        lower, upper = self.partitions.fuzzify(x.reshape(inputs * tables, count))
        lower = lower.reshape(x.shape)
        upper = upper.reshape(x.shape)
        base = (lower * self.strides[..., None]).sum(axis=0)
        degree = np.empty((inputs, 2, tables, count))  # (n, 2, T, N): lower set's, upper set's
        np.subtract(1.0, upper, out=degree[:, 0])
        degree[:, 1] = upper
        strength = degree[0]
        for k in range(1, inputs):
            strength = np.minimum(strength[:, None], degree[k]).reshape(-1, tables, count)
        return base, strength


@dataclass(frozen=True, slots=True, eq=False)
class TableTraining:
    """How training fires one table, unpadded, straight into its (rule, column) entries, and
    the room it sums in."""

    pass_sonars: np.ndarray  # (2, g, n) the inputs' sonar groups, as read and mirrored
    partitions: tuple[np.ndarray, ...]  # the n inputs' StackedPartitions arrays
    strides: np.ndarray  # (n,) entry step of each input's set
    corner_offsets: np.ndarray  # (2^n,) each corner's entry from the lowest
    # The first h inputs, whose corners' strengths are kept apart from the other n - h's:
    # two half tables small enough for the core's cache, where the whole 2^n would not be.
    high_inputs: int
    chunk_rows: int  # exemplars summed apart before joining a batch's sums
    sums: np.ndarray  # (4, E) a batch's and a chunk's sums of w and w * v; zero between batches
    met: np.ndarray  # (2, E) the entries a batch and a chunk met

    @classmethod
    def of(cls, table: FamTable) -> TableTraining:
        firing = Firing.of((table,), (0,), len(table.inputs), scale=len(table.trajectories))
        p = firing.partitions
        entries = table.rule_count * len(table.trajectories)
        return cls(
            np.stack([firing.sonars[..., 0], firing.mirrored().sonars[..., 0]]),
            (p.interior_m, p.gap_start, p.gap_low_m, p.gap_width_m),
            firing.strides[:, 0],
            firing.corners[:, 0],
            len(table.inputs) // 2,
            max(1, TRAIN_CHUNK_CORNERS // len(firing.corners)),
            np.zeros((4, entries)),
            np.empty((2, entries), dtype=np.intp),
        )
