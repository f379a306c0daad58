"""Means over seeds with a 95 % interval: Student's t quantiles as tables print them, intervals
that cover the true mean 95 % of the time, and rows grouped by their settings."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tvl_cli.analysis.intervals import Interval, group_intervals, interval, t_975


@pytest.mark.parametrize(
    "freedoms, quantile",
    # Student's t, 0.975 quantile, from a printed table (Fisher and Yates) and, beyond 30
    # degrees of freedom, from the exact inverse of its distribution.
    [(1, 12.706), (2, 4.303), (4, 2.776), (9, 2.262), (29, 2.045), (30, 2.042),
     (31, 2.0395), (40, 2.0211), (60, 2.0003), (120, 1.9799), (10_000, 1.9602)],
)  # fmt: skip
def test_t_quantile_is_students(freedoms: int, quantile: float) -> None:
    assert t_975(freedoms) == pytest.approx(quantile, abs=5e-4)


def test_t_quantile_needs_a_degree_of_freedom() -> None:
    with pytest.raises(ValueError, match="1 degree of freedom"):
        t_975(0)


def test_three_values_have_the_t_interval_of_their_standard_error() -> None:
    shown = interval([1.0, 2.0, 3.0])  # mean 2, standard deviation 1
    assert shown is not None
    assert (shown.mean, shown.n) == (2.0, 3)
    assert shown.half_width == pytest.approx(4.302653 / math.sqrt(3))


def test_one_value_has_a_mean_and_no_interval_and_none_has_neither() -> None:
    assert interval([0.4]) == Interval(0.4, None, 1)
    assert interval([]) is None


@pytest.mark.parametrize("seeds", [3, 10])
def test_the_interval_covers_the_true_mean_95_percent_of_the_time(seeds: int) -> None:
    rng = np.random.default_rng(26)
    trials = 4000
    covered = 0
    for sample in rng.normal(0.3, 0.05, size=(trials, seeds)):
        shown = interval(list(sample))
        assert shown is not None and shown.half_width is not None
        covered += abs(shown.mean - 0.3) <= shown.half_width
    # The share of 4000 trials varies by 0.0034 (one standard deviation): the bounds are 4
    # of those away. A normal interval (z = 1.96) would cover about 81 % with 3 seeds.
    assert 0.935 <= covered / trials <= 0.965


def test_rows_group_by_their_settings_in_the_order_they_come() -> None:
    rows = [
        {"config": "single", "seed": 1, "speed": 0.2, "clearance": None, "reached": True},
        {"config": "multi", "seed": 1, "speed": 0.5, "clearance": 0.3, "reached": False},
        {"config": "single", "seed": 2, "speed": 0.4, "clearance": 0.6, "reached": False},
    ]
    single, multi = group_intervals(rows, ["config"], ["speed", "clearance", "reached"])
    assert (single.key, single.rows, multi.key, multi.rows) == (("single",), 2, ("multi",), 1)
    assert single.intervals["speed"] is not None
    assert single.intervals["speed"].mean == pytest.approx(0.3)
    # A measure a run did not take is left out; true and false count as a share.
    assert single.intervals["clearance"] == Interval(0.6, None, 1)
    assert single.intervals["reached"] is not None
    assert single.intervals["reached"].mean == 0.5
    assert multi.intervals["speed"] == Interval(0.5, None, 1)


def test_a_measure_no_run_took_has_no_interval() -> None:
    (group,) = group_intervals([{"k": 1, "m": None}, {"k": 1, "m": None}], ["k"], ["m"])
    assert group.intervals["m"] is None
