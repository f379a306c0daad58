"""The Dynamic Window Approach's pure parts: window, arcs, free distances, admissibility, score."""

from __future__ import annotations

import math

import numpy as np
import pytest
from kernel_references.dwa_reference import free_distances_reference

from tvl_cli.baselines.dwa_window import (
    Candidates,
    DwaParams,
    admissible,
    arc_lengths,
    arc_points,
    best_candidate,
    clearance_read_m,
    dynamic_window,
    heading_scores,
    lookahead_m,
    predicted_poses,
    recovery_spin,
    wander_heading,
)

P = DwaParams()


def candidates(*pairs: tuple[float, float]) -> Candidates:
    v, w = zip(*pairs, strict=True)
    return Candidates(np.array(v, dtype=float), np.array(w, dtype=float))


def test_window_spans_one_period_of_acceleration_around_the_current_velocity() -> None:
    window = dynamic_window(0.3, 0.0, 0.1, P)
    assert window.v_mps.min() == pytest.approx(0.25) and window.v_mps.max() == pytest.approx(0.35)
    assert window.w_radps.min() == pytest.approx(-0.2) and window.w_radps.max() == pytest.approx(
        0.2
    )
    assert len(window.v_mps) == P.v_samples * P.w_samples


def test_window_is_clipped_to_the_speed_limits() -> None:
    fast = dynamic_window(0.6, 1.0, 0.1, P)
    assert fast.v_mps.max() == pytest.approx(0.6) and fast.w_radps.max() == pytest.approx(1.0)
    stopped = dynamic_window(0.0, 0.0, 0.1, P)
    assert stopped.v_mps.min() == 0.0


def test_arc_points_lie_on_the_circle_of_the_candidate_radius() -> None:
    s = arc_lengths(P)
    points = arc_points((1.0, 2.0, 0.0), candidates((0.5, 0.5)), s)[0]  # radius 1 m, left
    np.testing.assert_allclose(np.hypot(points[:, 0] - 1.0, points[:, 1] - 3.0), 1.0)
    # The arc length from the start is the angle turned times the radius.
    turned = np.unwrap(np.arctan2(points[:, 1] - 3.0, points[:, 0] - 1.0)) + math.pi / 2
    np.testing.assert_allclose(turned, s)


def test_straight_arcs_follow_the_heading_and_a_spin_stays_put() -> None:
    s = arc_lengths(P)
    straight, spin = arc_points((1.0, 2.0, math.pi / 2), candidates((0.4, 0.0), (0.0, 1.0)), s)
    np.testing.assert_allclose(straight, np.stack([np.ones_like(s), 2.0 + s], 1), atol=1e-12)
    np.testing.assert_allclose(spin, np.tile([1.0, 2.0], (len(s), 1)))


def test_free_distance_stops_at_the_last_point_outside_the_margin() -> None:
    s = np.array([0.1, 0.2, 0.3, 0.4])
    clearance = np.array([[0.3, 0.2, 0.1, 0.0], [0.4, 0.5, 0.6, 0.7]])
    free = free_distances_reference(clearance, 0.4, s, P.margin_m)
    # Row 0: first point within the 0.05 m margin is the 4th; before it 0.05 m spare at 0.3 m.
    assert free[0] == pytest.approx(0.35)
    assert free[1] == pytest.approx(0.4)  # never near: free to the end


def test_free_distance_inside_the_margin_allows_moving_away_but_not_closer() -> None:
    s = np.array([0.1, 0.2, 0.3])
    away, closer = free_distances_reference(
        np.array([[0.03, 0.04, 0.2], [0.01, 0.0, 0.0]]), 0.02, s, P.margin_m
    )
    assert away == pytest.approx(0.3)
    assert closer == pytest.approx(0.0)


@pytest.mark.parametrize("start_m", [0.01, 0.03, 0.05, 0.3])
def test_clearances_beyond_what_is_read_give_the_same_free_distances(start_m: float) -> None:
    # Clearances spread about the bound, many within a step of it either side: the nearest
    # search may stop there (inf beyond) without changing any free distance.
    s = arc_lengths(P)
    read = clearance_read_m(s, P)
    rng = np.random.default_rng(5)
    clearance = rng.uniform(0.0, 3.0 * read, size=(400, len(s)))
    clearance[::3] = np.sort(clearance[::3], axis=1)[:, ::-1]  # arcs closing in on something
    clipped = np.where(clearance > read, np.inf, clearance)
    assert np.isinf(clipped).any() and (clipped > 0.0).any()
    exact = free_distances_reference(clearance, start_m, s, P.margin_m)
    np.testing.assert_array_equal(free_distances_reference(clipped, start_m, s, P.margin_m), exact)
    assert len(np.unique(exact)) > 10  # the rows do differ


def test_what_is_read_is_the_margin_and_the_longest_step_along_an_arc() -> None:
    s = np.array([0.1, 0.15, 0.3, 0.35])
    assert clearance_read_m(s, P) == pytest.approx(P.margin_m + 0.15, abs=1e-5)


def test_admissible_speeds_can_stop_within_the_free_distance() -> None:
    ok = admissible(np.array([0.5, 0.5, 0.0]), np.array([0.25, 0.24, 0.0]), P)
    assert ok.tolist() == [True, False, True]  # sqrt(2 * 0.5 * 0.25) = 0.5


def test_score_weighs_heading_clearance_and_velocity() -> None:
    options = candidates((0.6, 0.0), (0.3, 0.0), (0.6, 0.5))
    free = np.array([0.5, 1.2, 1.2])
    heading = np.array([1.0, 1.0, 0.8])
    expected = (
        P.heading_weight * heading
        + P.clearance_weight * np.minimum(free, options.v_mps * P.horizon_s) / lookahead_m(P)
        + P.velocity_weight * options.v_mps / P.v_max_mps
    )
    assert best_candidate(options, free, heading, P) == int(np.argmax(expected)) == 2


def test_inadmissible_candidates_are_never_chosen() -> None:
    options = candidates((0.6, 0.0), (0.4, 0.0))
    # The faster one would score higher, but cannot stop within 0.1 m.
    assert best_candidate(options, np.array([0.1, 0.2]), np.ones(2), P) == 1


def test_with_nothing_admissible_it_brakes_hardest_towards_the_most_room() -> None:
    options = candidates((0.5, -0.2), (0.5, 0.2), (0.6, 0.2))
    assert best_candidate(options, np.array([0.01, 0.02, 0.03]), np.ones(3), P) == 1


def test_heading_score_is_one_aligned_and_zero_opposite() -> None:
    predicted = np.array(
        [[0.0, 0.0, 0.3], [0.0, 0.0, 0.3 + math.pi / 2], [0.0, 0.0, 0.3 - math.pi]]
    )
    np.testing.assert_allclose(heading_scores(predicted, 0.3), [1.0, 0.5, 0.0], atol=1e-12)


def test_predicted_pose_adds_braking_to_one_period() -> None:
    (pose,) = predicted_poses((0.0, 0.0, 0.0), candidates((0.4, 0.0)), 0.1, P)
    assert pose[0] == pytest.approx(0.4 * 0.1 + 0.4**2 / (2 * P.accel_mps2))
    assert pose[1:] == pytest.approx([0.0, 0.0])


def test_wander_goes_straight_on_while_that_is_free() -> None:
    offsets = np.array([-math.pi / 2, 0.0, math.pi / 2])
    free = np.array([2.0, lookahead_m(P), 2.0])
    assert wander_heading(1.0, offsets, free, P, side=1) == 1.0


def test_wander_turns_to_the_freest_ray_and_breaks_ties_to_its_side() -> None:
    offsets = np.array([-math.pi / 2, 0.0, math.pi / 2, math.pi])
    assert wander_heading(0.0, offsets, np.array([0.3, 0.2, 0.9, 1.0]), P, side=1) == math.pi
    tied = np.array([0.9, 0.2, 0.9, 0.3])
    assert wander_heading(0.0, offsets, tied, P, side=-1) == -math.pi / 2
    assert wander_heading(0.0, offsets, tied, P, side=1) == math.pi / 2


def test_recovery_spin_turns_on_the_spot_towards_the_side() -> None:
    options = candidates((0.0, -0.2), (0.0, 0.0), (0.0, 0.2), (0.05, 0.2))
    assert recovery_spin(options, side=1) == 2
    assert recovery_spin(options, side=-1) == 0
