"""Velocity labels from the distance still to go to the collision point."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tvl_cli.core.errors import BadInput
from tvl_cli.core.labels import (
    DEFAULT_DECEL_MPS2,
    DEFAULT_MARGIN_M,
    distances_to_collision,
    velocity_labels,
)


def test_labels_follow_the_braking_speed_before_the_collision() -> None:
    distances = np.array([0.06, 0.1, 0.2, 0.3])
    expected = [math.sqrt(2 * 0.5 * (d - 0.05)) for d in distances]
    labels = velocity_labels(distances, 1.0, decel_mps2=0.5, margin_m=0.05)
    np.testing.assert_allclose(labels, expected, rtol=1e-15)


def test_default_labels_brake_at_the_default_deceleration_short_of_the_margin() -> None:
    d = DEFAULT_MARGIN_M + 0.2
    expected = math.sqrt(2 * DEFAULT_DECEL_MPS2 * 0.2)
    assert velocity_labels(np.array([d]), 10.0)[0] == pytest.approx(expected, rel=1e-12)


def test_labels_are_capped_at_the_trajectory_maximum() -> None:
    labels = velocity_labels(np.array([0.2, 1.0, 5.0]), 0.55, decel_mps2=0.5, margin_m=0.05)
    assert labels[0] == pytest.approx(math.sqrt(0.15))
    assert labels[1:].tolist() == [0.55, 0.55]


def test_points_within_the_margin_are_labelled_zero() -> None:
    distances = np.array([0.0, 0.5 * DEFAULT_MARGIN_M, DEFAULT_MARGIN_M])
    assert velocity_labels(distances, 0.6).tolist() == [0.0, 0.0, 0.0]


def test_a_full_circle_labels_every_point_v_max() -> None:
    distances = distances_to_collision(np.linspace(0.0, 3.1, 30), collided=False)
    assert np.isinf(distances).all()
    assert (velocity_labels(distances, 0.45) == 0.45).all()


def test_each_point_may_have_its_own_v_max() -> None:
    labels = velocity_labels(np.array([np.inf, np.inf, 0.05]), np.array([0.35, 0.6, 0.6]))
    assert labels.tolist() == [0.35, 0.6, 0.0]


def test_deceleration_and_margin_change_the_labels() -> None:
    label = velocity_labels(np.array([1.0]), 2.0, decel_mps2=2.0, margin_m=0.1)[0]
    assert label == pytest.approx(math.sqrt(2 * 2.0 * 0.9))


def test_distances_run_to_the_last_point_of_a_collision() -> None:
    distances = distances_to_collision(np.array([0.0, 0.02, 0.05, 0.1]), collided=True)
    np.testing.assert_allclose(distances, [0.1, 0.08, 0.05, 0.0])


def test_distances_run_to_a_given_collision_arc() -> None:
    distances = distances_to_collision(np.array([0.0, 0.5]), collided=True, end_arc_m=0.52)
    np.testing.assert_allclose(distances, [0.52, 0.02])


@pytest.mark.parametrize("decel", [0.0, -0.5, math.inf, math.nan])
def test_a_deceleration_that_is_not_positive_is_refused(decel: float) -> None:
    with pytest.raises(BadInput, match="deceleration"):
        velocity_labels(np.array([1.0]), 0.5, decel_mps2=decel)


def test_a_negative_margin_is_refused() -> None:
    with pytest.raises(BadInput, match="margin"):
        velocity_labels(np.array([1.0]), 0.5, margin_m=-0.01)
