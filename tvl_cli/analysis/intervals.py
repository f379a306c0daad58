"""Means over trials with their 95 % confidence interval (Student's t), as a sweep reports
each setting over its seeds.

The trials of one setting are few (3 to 10 seeds), so the interval is Student's t on their
sample standard deviation, not the normal one: with 3 seeds it is 2.2 times as wide.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

Row = dict[str, Any]

# The 0.975 quantile of Student's t (a two-sided 95 % interval) for 1 to 30 degrees of
# freedom, as printed in statistics tables.
_T_975 = (
    12.706205, 4.302653, 3.182446, 2.776445, 2.570582, 2.446912, 2.364624, 2.306004,
    2.262157, 2.228139, 2.200985, 2.178813, 2.160369, 2.144787, 2.131450, 2.119905,
    2.109816, 2.100922, 2.093024, 2.085963, 2.079614, 2.073873, 2.068658, 2.063899,
    2.059539, 2.055529, 2.051831, 2.048407, 2.045230, 2.042272,
)  # fmt: skip
_Z_975 = statistics.NormalDist().inv_cdf(0.975)  # 1.959964: the limit of many freedoms


def t_975(freedoms: int) -> float:
    """The 0.975 quantile of Student's t with `freedoms` degrees of freedom (1 or more)."""
    if freedoms < 1:
        raise ValueError(f"Student's t needs 1 degree of freedom or more, not {freedoms}")
    if freedoms <= len(_T_975):
        return _T_975[freedoms - 1]
    # Beyond the table, the Cornish-Fisher expansion about the normal quantile: within 1e-7
    # of the exact value from 30 degrees of freedom on.
    z, v = _Z_975, float(freedoms)
    return (
        z
        + (z**3 + z) / (4 * v)
        + (5 * z**5 + 16 * z**3 + 3 * z) / (96 * v**2)
        + (3 * z**7 + 19 * z**5 + 17 * z**3 - 15 * z) / (384 * v**3)
        + (79 * z**9 + 776 * z**7 + 1482 * z**5 - 1920 * z**3 - 945 * z) / (92160 * v**4)
    )


Bounds = tuple[float | None, float | None]  # what a measure can be: (least, most); None: any
NO_BOUNDS: Bounds = (None, None)


@dataclass(frozen=True, slots=True)
class Interval:
    """The mean of `n` values and its 95 % interval, mean ± half_width, within the bounds of
    what the values can be: from few seeds, Student's t can reach below 0 for a measure that
    never is (a rate of contacts), and the interval then stops at 0."""

    mean: float
    half_width: float | None  # None from one value: its spread is unknown
    n: int
    bounds: Bounds = NO_BOUNDS

    @property
    def low(self) -> float | None:
        if self.half_width is None:
            return None
        least = self.bounds[0]
        low = self.mean - self.half_width
        return low if least is None else max(low, least)

    @property
    def high(self) -> float | None:
        if self.half_width is None:
            return None
        most = self.bounds[1]
        high = self.mean + self.half_width
        return high if most is None else min(high, most)

    @property
    def clipped(self) -> bool:
        """Whether a bound cuts the interval, so that it is no longer mean ± half_width."""
        if self.half_width is None:
            return False
        return (self.low, self.high) != (self.mean - self.half_width, self.mean + self.half_width)

    def scaled(self, scale: float) -> Interval:
        """The interval of the values times `scale` (> 0): a share as a percentage."""
        half = None if self.half_width is None else self.half_width * scale
        bounds = tuple(None if b is None else b * scale for b in self.bounds)
        return Interval(self.mean * scale, half, self.n, bounds)  # type: ignore[arg-type]


def interval(values: Sequence[float], bounds: Bounds = NO_BOUNDS) -> Interval | None:
    """The mean and 95 % interval of the values, within `bounds`; None if there are none."""
    if not values:
        return None
    mean = statistics.fmean(values)
    if len(values) < 2:
        return Interval(mean, None, 1, bounds)
    spread = statistics.stdev(values) / math.sqrt(len(values))
    return Interval(mean, t_975(len(values) - 1) * spread, len(values), bounds)


@dataclass(frozen=True, slots=True)
class Group:
    """Rows alike in the grouping keys, with each measure's interval over them."""

    key: tuple[Any, ...]  # the rows' values of the grouping keys
    rows: int
    intervals: dict[str, Interval | None]  # by measure; None where no row took it


def group_intervals(
    rows: Iterable[Row],
    by: Sequence[str],
    measures: Sequence[str],
    bounds: Mapping[str, Bounds] | None = None,
) -> list[Group]:
    """The rows grouped by their values of `by`, in the order the groups first appear, with
    each measure's interval over the group, within its `bounds` if given. A measure a run did
    not take (null) is left out of its mean, and true or false count as 1 or 0: the mean is
    then a share."""
    bounds = bounds or {}
    groups: dict[tuple[Any, ...], list[Row]] = {}
    for row in rows:
        groups.setdefault(tuple(row.get(key) for key in by), []).append(row)
    return [
        Group(
            key,
            len(members),
            {
                measure: interval(
                    [float(row[measure]) for row in members if row.get(measure) is not None],
                    bounds.get(measure, NO_BOUNDS),
                )
                for measure in measures
            },
        )
        for key, members in groups.items()
    ]
