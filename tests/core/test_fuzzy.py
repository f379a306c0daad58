"""Ruspini partitions of triangles with shoulder ends."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tvl_cli.core.fam_config import PARTITIONS, Partition
from tvl_cli.core.fuzzy import StackedPartitions, memberships

FIVE = PARTITIONS[5]  # centres 0.20 0.45 0.80 1.30 2.00


def full_degrees(partition: Partition, x: np.ndarray) -> np.ndarray:
    """(N, K) membership of every set, from the compact (lower, upper) form."""
    lower, upper = memberships(partition, x)
    out = np.zeros((len(x), len(partition.centres_m)))
    out[np.arange(len(x)), lower] = 1.0 - upper
    out[np.arange(len(x)), lower + 1] += upper
    return out


def interp_degrees(partition: Partition, x: np.ndarray) -> np.ndarray:
    """(N, K) the same memberships by np.interp: a triangle per set, flat beyond the ends."""
    centres = np.asarray(partition.centres_m)
    return np.stack([np.interp(x, centres, row) for row in np.eye(len(centres))], axis=1)


def test_below_the_first_centre_only_the_first_set_fires() -> None:
    lower, upper = memberships(FIVE, np.array([0.0, 0.1, 0.2]))
    assert lower.tolist() == [0, 0, 0]
    assert upper.tolist() == [0.0, 0.0, 0.0]


def test_above_the_last_centre_only_the_last_set_fires() -> None:
    lower, upper = memberships(FIVE, np.array([2.0, 3.5, np.inf]))
    assert lower.tolist() == [3, 3, 3]
    assert upper.tolist() == [1.0, 1.0, 1.0]


def test_a_reading_on_a_centre_fires_that_set_alone_with_degree_one() -> None:
    degrees = full_degrees(FIVE, np.array(FIVE.centres_m))
    np.testing.assert_array_equal(degrees, np.eye(5))


def test_halfway_between_centres_splits_evenly() -> None:
    partition = Partition(("N", "M", "F"), (0.25, 0.5, 1.0))
    lower, upper = memberships(partition, np.array([0.375, 0.75]))
    assert lower.tolist() == [0, 1]
    assert upper.tolist() == [0.5, 0.5]


@given(st.lists(st.floats(-1.0, 6.0), min_size=1, max_size=50))
def test_memberships_sum_to_one_and_match_interpolated_triangles(values: list[float]) -> None:
    x = np.array(values)
    for partition in PARTITIONS.values():
        degrees = full_degrees(partition, x)
        np.testing.assert_allclose(degrees.sum(axis=1), 1.0, rtol=0, atol=1e-12)
        np.testing.assert_allclose(degrees, interp_degrees(partition, x), rtol=0, atol=1e-12)
        assert ((degrees > 0).sum(axis=1) <= 2).all()


@given(st.lists(st.floats(0.0, 5.0) | st.just(np.inf), min_size=4, max_size=4))
def test_stacked_partitions_fuzzify_each_row_by_its_own_partition(values: list[float]) -> None:
    partitions = [PARTITIONS[5], PARTITIONS[2], PARTITIONS[4], PARTITIONS[3]]
    x = np.array(values)[:, None]  # (4, 1): one reading per partition
    lower, upper = StackedPartitions.of(partitions).fuzzify(x)
    for j, partition in enumerate(partitions):
        one_lower, one_upper = memberships(partition, x[j])
        assert lower[j].tolist() == one_lower.tolist()
        assert upper[j].tolist() == one_upper.tolist()


def test_memberships_keep_the_shape_of_their_input() -> None:
    lower, upper = memberships(FIVE, np.full((3, 4), 0.5))
    assert lower.shape == upper.shape == (3, 4)


@pytest.mark.parametrize("sets", sorted(PARTITIONS))
def test_shipped_partitions_are_denser_near_the_robot(sets: int) -> None:
    widths = np.diff(PARTITIONS[sets].centres_m)
    assert (np.diff(widths) > 0).all()
