"""The trajectories as paths in the plane: where a body's centre is after some arc length of
one, and how far it can travel along one before the body meets a point.

A trajectory of curvature k (1 / radius; positive turns left, 0 is straight) from the pose
(x, y, theta) is the circle through (x, y) tangent to the heading, travelled
counter-clockwise for k > 0.
"""

from __future__ import annotations

import math

import numpy as np

from tvl_cli.core.robot_config import RobotConfig

Pose = tuple[float, float, float]


def collision_clearance_m(robot: RobotConfig) -> float:
    """How near the body may come to an obstacle before a way counts as blocked there, heard
    or true: the sonar's minimum range. Nearer, the ring cannot tell near from touching, and
    an arc that passes an echo closer than that grazes it once odometry has drifted."""
    return robot.sonar.min_range_m


def arc_points(pose: Pose, curvature_per_m: float, along_m: np.ndarray) -> np.ndarray:
    """(S, 2) metres: the body's centre after each arc length of `along_m` (S,) metres."""
    x, y, theta = pose
    s = np.asarray(along_m, dtype=np.float64)
    if curvature_per_m == 0.0:
        return np.stack([x + s * math.cos(theta), y + s * math.sin(theta)], axis=1)
    heading = theta + curvature_per_m * s  # (S,) rad
    return np.stack(
        [
            x + (np.sin(heading) - math.sin(theta)) / curvature_per_m,
            y - (np.cos(heading) - math.cos(theta)) / curvature_per_m,
        ],
        axis=1,
    )


def first_contacts_m(
    pose: Pose, curvatures_per_m: np.ndarray, points_xy: np.ndarray, body_radius_m: float
) -> np.ndarray:
    """(T,) the arc length (m) the body's centre can travel from `pose` along each of the
    trajectories of `curvatures_per_m` (T,) before the body meets one of the points (K, 2);
    inf where it meets none (within a full circle, for an arc).

    Points the body overlaps already are left out: a body that has not bumped touches
    nothing, so such a point is an echo placed off its object (a cone's reading put on its
    axis, odometry's drift).
    """
    x, y, theta = pose
    points = np.asarray(points_xy, dtype=np.float64).reshape(-1, 2)
    dx, dy = points[:, 0] - x, points[:, 1] - y  # (K,) metres
    ahead = dx * math.cos(theta) + dy * math.sin(theta)  # (K,) along the heading
    left = dy * math.cos(theta) - dx * math.sin(theta)  # (K,) to its left
    r = body_radius_m
    outside = ahead**2 + left**2 > r**2  # (K,)
    curvature = np.asarray(curvatures_per_m, dtype=np.float64)  # (T,)
    found = np.full(len(curvature), math.inf)
    straight = curvature == 0.0
    if straight.any():
        met = outside & (np.abs(left) <= r) & (ahead > 0.0)
        along = ahead - np.sqrt(np.maximum(r**2 - left**2, 0.0))
        found[straight] = along[met].min() if met.any() else math.inf
    turning = ~straight
    if turning.any():
        k = curvature[turning][:, None]  # (A, 1)
        radius = 1.0 / np.abs(k)
        # A right turn is the left turn of the mirrored points. About the turn's centre,
        # (0, radius) to the left, the robot stands at -90° and moves counter-clockwise.
        across = np.sign(k) * left[None, :] - radius  # (A, K)
        rho = np.hypot(ahead[None, :], across)  # (A, K) metres from the centre
        bearing = np.mod(np.arctan2(across, ahead[None, :]) + math.pi / 2, 2 * math.pi)
        # The body's centre is within r of a point for a half-angle alpha either side of it.
        reach = outside[None, :] & (np.abs(rho - radius) <= r)
        with np.errstate(divide="ignore", invalid="ignore"):
            cos_alpha = (radius**2 + rho**2 - r**2) / (2 * radius * rho)
        alpha = np.arccos(np.clip(np.where(reach, cos_alpha, 1.0), -1.0, 1.0))
        turned = bearing - alpha  # (A, K) rad: > 0 for every point outside the body
        met = reach & (turned > 0.0)
        arcs = np.where(met, radius * turned, math.inf)
        found[turning] = arcs.min(axis=1) if arcs.shape[1] else math.inf
    return found


def first_contact_m(
    pose: Pose, curvature_per_m: float, points_xy: np.ndarray, body_radius_m: float
) -> float:
    """first_contacts_m of one trajectory."""
    return float(first_contacts_m(pose, np.array([curvature_per_m]), points_xy, body_radius_m)[0])
