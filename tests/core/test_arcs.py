"""The trajectories as paths (core.arcs): where the body's centre goes along one, and how far
it may go before the body meets a point."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tvl_cli.core.arcs import arc_points, first_contact_m, first_contacts_m
from tvl_cli.core.robot_config import RobotConfig

ROBOT = RobotConfig()
R = ROBOT.radius_m
CURVATURES = np.array([t.curvature_per_m for t in ROBOT.trajectories])


def test_an_arc_of_a_quarter_circle_ends_a_radius_across() -> None:
    quarter = math.pi / 2  # of a unit circle, turning left from the origin heading +x
    np.testing.assert_allclose(arc_points((0.0, 0.0, 0.0), 1.0, np.array([quarter])), [[1, 1]])
    np.testing.assert_allclose(arc_points((0.0, 0.0, 0.0), -1.0, np.array([quarter])), [[1, -1]])
    np.testing.assert_allclose(arc_points((1.0, 2.0, math.pi / 2), 0.0, np.array([3.0])), [[1, 5]])


def test_a_straight_path_meets_the_nearest_point_in_the_body_s_way() -> None:
    points = np.array([[1.0, 0.1], [2.0, 0.0], [0.5, 0.5], [-1.0, 0.0]])
    # (1.0, 0.1) is met when the centre is sqrt(0.2² - 0.1²) short of it; the others lie
    # wide of the path or behind it.
    assert first_contact_m((0.0, 0.0, 0.0), 0.0, points, R) == pytest.approx(
        1.0 - math.sqrt(R**2 - 0.1**2)
    )
    assert first_contact_m((0.0, 0.0, 0.0), 0.0, points[2:], R) == math.inf


def test_an_arc_meets_a_point_on_its_circle_a_body_radius_early() -> None:
    # A left turn of radius 1 from the origin heading +x circles (0, 1); the point (1, 1) lies
    # a quarter turn round, and the body meets it when its centre is the angle alpha short.
    alpha = math.acos((2.0 - R**2) / 2.0)
    on_circle = np.array([[1.0, 1.0]])
    assert first_contact_m((0.0, 0.0, 0.0), 1.0, on_circle, R) == pytest.approx(math.pi / 2 - alpha)
    # The same point mirrored is met by the right turn alike, and missed by the left one.
    mirrored = np.array([[1.0, -1.0]])
    assert first_contact_m((0.0, 0.0, 0.0), -1.0, mirrored, R) == pytest.approx(math.pi / 2 - alpha)
    assert first_contact_m((0.0, 0.0, 0.0), 1.0, mirrored, R) == math.inf


def test_points_the_body_overlaps_now_are_left_out() -> None:
    inside = np.array([[0.1, 0.0], [0.0, -0.15]])
    assert first_contact_m((0.0, 0.0, 0.0), 0.0, inside, R) == math.inf
    assert first_contact_m((0.0, 0.0, 0.0), 2.0, inside, R) == math.inf


def test_every_trajectory_at_once_is_each_alone() -> None:
    rng = np.random.default_rng(7)
    points = rng.uniform(-3, 3, (400, 2))
    pose = (0.3, -0.2, 0.8)
    together = first_contacts_m(pose, CURVATURES, points, R)
    alone = [first_contact_m(pose, k, points, R) for k in CURVATURES]
    np.testing.assert_array_equal(together, alone)
    assert np.isfinite(together).all()


@pytest.mark.parametrize("curvature", list(CURVATURES))
def test_the_body_centre_is_a_radius_from_the_point_it_meets(curvature: float) -> None:
    rng = np.random.default_rng(3)
    points = rng.uniform(-3, 3, (300, 2))
    pose = (0.0, 0.0, 0.3)
    along = first_contact_m(pose, curvature, points, R)
    centre = arc_points(pose, curvature, np.array([along]))[0]
    assert np.hypot(*(points - centre).T).min() == pytest.approx(R, abs=1e-9)
    # Just before, every point is clear of the body.
    before = arc_points(pose, curvature, np.array([along - 1e-3]))[0]
    assert np.hypot(*(points - before).T).min() > R
