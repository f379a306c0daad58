"""The heard labels' kernel (core.heard): for many poses, how far the body can travel along
each trajectory before it meets one of the echoes in the pose's own window of them.

`first_contacts_in_windows` is compiled; core.arcs.first_contacts_m computes the same for
one pose in numpy, with no reach, which the tests hold it to.
"""

from __future__ import annotations

import math

from tvl_cli.core.numba_kernel import kernel

# The squared-distance screen's margins: far wider than the rounding of either test, so that it
# leaves out only echoes the exact test would leave out too.
_SLACK_OUT = 1.0 + 1e-9
_SLACK_IN = 1.0 - 1e-9


@kernel
def first_contacts_in_windows(
    poses, curvatures, points, first, stop, body_radius_m, reach_m, nearest_first, found
):  # fmt: skip
    """Fill found (N, T) with the arc length (m) the body's centre can travel from each pose
    of poses (N, 3) x, y, theta along each trajectory of curvatures (T,) 1/m before the body
    meets one of points[first[i]:stop[i]] (points (M, 2) metres); inf where it meets none
    nearer than reach_m along it (reach_m inf: at any length). Points the body overlaps
    already are left out.

    No arc is shorter than its chord, so the body meets a point no sooner than the point's
    distance from the pose less the body's radius: a point is tested against a trajectory
    only while that is below the nearest contact found on it so far (reach_m at first), and
    most of a window's points are passed over without the exact test. With nearest_first,
    each window's points lie in order of distance from its pose, so the first that none of
    the trajectories can meet sooner than found ends the window: the rest lie farther."""
    r = body_radius_m
    within_squared = (reach_m + r) * (reach_m + r)
    for i in range(poses.shape[0]):
        x, y, theta = poses[i, 0], poses[i, 1], poses[i, 2]
        c, s = math.cos(theta), math.sin(theta)
        for t in range(curvatures.shape[0]):
            found[i, t] = reach_m
        farthest = reach_m  # the farthest contact found on any trajectory, or the reach
        for k in range(first[i], stop[i]):
            dx, dy = points[k, 0] - x, points[k, 1] - y
            ahead = dx * c + dy * s
            left = dy * c - dx * s
            distance_squared = ahead * ahead + left * left
            if distance_squared <= r * r:
                continue  # overlapped already: placed off its object
            if distance_squared > within_squared:
                if nearest_first:
                    break
                continue  # beyond the reach along any trajectory
            if nearest_first and distance_squared > (farthest + r) * (farthest + r) * _SLACK_OUT:
                break  # met on no trajectory sooner than what is found on it, nor are the rest
            improved = False
            for t in range(curvatures.shape[0]):
                # Met no sooner than its distance less the body: it cannot better what is found.
                bound = found[i, t] + r
                if distance_squared > bound * bound * _SLACK_OUT:
                    continue
                k_t = curvatures[t]
                if k_t == 0.0:
                    if abs(left) <= r and ahead > 0.0:
                        along = ahead - math.sqrt(max(r * r - left * left, 0.0))
                        if along < found[i, t]:
                            found[i, t] = along
                            improved = True
                    continue
                radius = 1.0 / abs(k_t)
                across = (1.0 if k_t > 0.0 else -1.0) * left - radius
                # Most echoes lie far off the swept band: ruled out by their squared distance
                # from the arc's centre, with room for rounding, before the exact test below.
                rho_squared = ahead * ahead + across * across
                if rho_squared > (radius + r) * (radius + r) * _SLACK_OUT:
                    continue
                if radius > r and rho_squared < (radius - r) * (radius - r) * _SLACK_IN:
                    continue
                rho = math.hypot(ahead, across)
                if abs(rho - radius) > r:
                    continue
                bearing = (math.atan2(across, ahead) + math.pi / 2) % (2 * math.pi)
                cos_alpha = (radius * radius + rho * rho - r * r) / (2 * radius * rho)
                cos_alpha = -1.0 if cos_alpha < -1.0 else (1.0 if cos_alpha > 1.0 else cos_alpha)
                turned = bearing - math.acos(cos_alpha)
                if turned > 0.0 and radius * turned < found[i, t]:
                    found[i, t] = radius * turned
                    improved = True
            if nearest_first and improved:  # only the nearest-first stop reads it
                farthest = found[i, 0]
                for t in range(1, curvatures.shape[0]):
                    farthest = found[i, t] if found[i, t] > farthest else farthest
        for t in range(curvatures.shape[0]):
            if found[i, t] >= reach_m:
                found[i, t] = math.inf
