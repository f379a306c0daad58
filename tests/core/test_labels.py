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
    label_reach_m,
    trajectory_ceilings,
    velocity_labels,
)
from tvl_cli.core.robot_config import DEFAULT_TRAJECTORIES


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


def test_a_ceiling_lets_a_label_tell_how_far_past_its_stopping_distance_a_way_is_clear() -> None:
    # T0's 0.6 m/s: at 0.1 m/s² with a 0.15 m margin the label reaches it 1.95 m out; with a
    # ceiling of 1.5 it goes on rising to 0.9 m/s, 4.2 m out, and stays there.
    distances = np.array([1.0, 1.95, 3.0, 4.2, 10.0, np.inf])
    capped = velocity_labels(distances, 0.6, 0.1, 0.15)
    lifted = velocity_labels(distances, 0.6, 0.1, 0.15, ceiling=1.5)
    assert capped[1:].tolist() == [0.6] * 5
    np.testing.assert_allclose(lifted[:4], np.sqrt(2 * 0.1 * (distances[:4] - 0.15)))
    assert lifted[4:].tolist() == [1.5 * 0.6] * 2
    assert lifted[0] == capped[0]  # below the top speed the ceiling changes nothing


def test_a_ceiling_of_one_labels_bit_for_bit_as_the_cap_at_the_top_speed() -> None:
    distances = np.random.default_rng(3).uniform(0.0, 5.0, 1000)
    top = np.random.default_rng(4).choice([0.35, 0.45, 0.55, 0.6], 1000)
    assert (
        velocity_labels(distances, top, ceiling=1.0).tobytes()
        == np.minimum(
            top, np.sqrt(2 * DEFAULT_DECEL_MPS2 * np.maximum(distances - DEFAULT_MARGIN_M, 0.0))
        ).tobytes()
    )


def test_the_reach_runs_to_where_the_lifted_label_stops_changing() -> None:
    reach = label_reach_m(0.6, 0.1, 0.15, ceiling=1.5)
    assert reach == pytest.approx(0.15 + 0.9**2 / 0.2)
    assert velocity_labels(np.array([reach]), 0.6, 0.1, 0.15, ceiling=1.5)[0] == 1.5 * 0.6
    assert label_reach_m(0.6, 0.1, 0.15) == pytest.approx(1.95)


@pytest.mark.parametrize("ceiling", [0.99, 3.01, math.nan])
def test_a_ceiling_below_the_top_speed_or_beyond_the_limit_is_refused(ceiling: float) -> None:
    with pytest.raises(BadInput, match="label ceiling"):
        velocity_labels(np.array([1.0]), 0.5, ceiling=ceiling)


def test_a_ceiling_radius_lifts_the_arcs_turning_no_wider_than_it_alone() -> None:
    radii = [t.radius_m for t in DEFAULT_TRAJECTORIES]  # T3L to T3R: 0.5, 1, 2, inf, 2, 1, 0.5
    assert trajectory_ceilings(radii, 1.5, 1.0).tolist() == [1.5, 1.5, 1, 1, 1, 1.5, 1.5]
    assert trajectory_ceilings(radii, 1.5, 0.5).tolist() == [1.5, 1, 1, 1, 1, 1, 1.5]
    assert trajectory_ceilings(radii, 1.5, None).tolist() == [1.5] * 7  # every trajectory


def test_each_label_may_have_its_own_ceiling() -> None:
    tops = np.array([t.v_max_mps for t in DEFAULT_TRAJECTORIES])
    ceilings = trajectory_ceilings([t.radius_m for t in DEFAULT_TRAJECTORIES], 1.5, 1.0)
    clear = velocity_labels(np.full(7, np.inf), tops, ceiling=ceilings)
    np.testing.assert_allclose(clear, tops * ceilings)
    with pytest.raises(BadInput, match="label ceiling"):
        velocity_labels(np.full(2, np.inf), 0.5, ceiling=np.array([1.0, 3.5]))
