"""The true collision points of the trajectories, from the map and the true pose: what the
references that read the map are given (the oracle labels and the oracle velocities of the
generalization benchmark), never any method.

A trajectory's true collision point from a pose is where the body, driven along it, first
touches a wall, pillar or ring wall: the same contact core.heard finds against echoes, found
against the world's outlines as points just so far apart that the body's edge passes within
half a millimetre of the outline between two of them, under the sonar's millimetre.
"""

from __future__ import annotations

import math

import numpy as np

from tvl_cli.core.labels import velocity_labels
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.worldmap import WorldMap

# How far the body's edge may pass inside the outline between two of its points: the points
# lie as far apart as that allows (outline_spacing_m), the fewer for a contact search to ask.
OUTLINE_TOLERANCE_M = 0.0005
# The outline's points are kept by the square cells of a grid this wide, so that the points
# near a place are gathered from the cells round it rather than sought among them all.
OUTLINE_CELL_M = 0.5


def outline_spacing_m(radius_m: float) -> float:
    """The most two points of an outline may lie apart for a circle of radius_m, touching
    both, to reach no more than OUTLINE_TOLERANCE_M past the straight line between them:
    twice the half-chord of the circle that deep."""
    depth = min(OUTLINE_TOLERANCE_M, radius_m)
    return 2.0 * math.sqrt(depth * (2.0 * radius_m - depth))


def outline_points(world: WorldMap, body_radius_m: float) -> np.ndarray:
    """(K, 2) metres: the world's walls, pillars and ring walls as points close enough that a
    body of body_radius_m passes no more than OUTLINE_TOLERANCE_M inside an outline between
    two of them. A wall is its own chord. Round a pillar the body's curve and the pillar's
    add up, as one circle of radius r R / (r + R) would; a ring wall curves away from the
    body inside it, whose chords are met first."""
    parts = [np.zeros((0, 2))]
    body_spacing_m = outline_spacing_m(body_radius_m)
    for x1, y1, x2, y2 in world.segments:
        n = max(2, math.ceil(math.hypot(x2 - x1, y2 - y1) / body_spacing_m) + 1)
        t = np.linspace(0.0, 1.0, n)[:, None]
        parts.append(np.array([x1, y1]) * (1 - t) + np.array([x2, y2]) * t)
    circles = [(disc, body_radius_m * disc[2] / (body_radius_m + disc[2])) for disc in world.discs]
    circles += [(ring, body_radius_m) for ring in world.rings]
    for (x, y, r), curve_m in circles:
        count = max(8, math.ceil(2 * math.pi * r / outline_spacing_m(curve_m)))
        angle = np.linspace(0.0, 2 * math.pi, count, endpoint=False)
        parts.append(np.stack([x + r * np.cos(angle), y + r * np.sin(angle)], axis=1))
    return np.concatenate(parts)


class TrueArcs:
    """The true collision points of a robot's trajectories in one world: where the body first
    comes within `clearance_m` of an obstacle (0: touches it)."""

    def __init__(self, world: WorldMap, robot: RobotConfig, clearance_m: float = 0.0) -> None:
        self._robot = robot
        self._body_radius_m = robot.radius_m + clearance_m  # the body grown by the clearance
        points = outline_points(world, self._body_radius_m)  # (K, 2) metres
        self._curvatures = np.array([t.curvature_per_m for t in robot.trajectories])
        self._low = points.min(axis=0) if len(points) else np.zeros(2)  # the grid's corner
        columns, rows = np.floor((points.max(axis=0, initial=0.0) - self._low) / OUTLINE_CELL_M)
        self._columns, self._rows = int(columns) + 1, int(rows) + 1
        cell = self._cells_of(points)  # (K,)
        order = np.argsort(cell, kind="stable")
        self._points = np.ascontiguousarray(points[order])  # cell by cell
        # Cell c's points are self._points[self._first[c]:self._first[c + 1]].
        self._first = np.searchsorted(cell[order], np.arange(self._columns * self._rows + 1))

    def _cells_of(self, points: np.ndarray) -> np.ndarray:
        """(K,) the grid cell of each of points (K, 2), row by row."""
        column, row = np.floor((points - self._low) / OUTLINE_CELL_M).astype(np.int64).T
        return row * self._columns + column

    def _near(self, x: float, y: float, within_m: float) -> np.ndarray:
        """(k, 2) the outline's points of the cells that hold every point within within_m of
        (x, y): what a trajectory from there can meet."""
        if not math.isfinite(within_m):
            return self._points
        low = np.floor((np.array([x, y]) - within_m - self._low) / OUTLINE_CELL_M)
        high = np.floor((np.array([x, y]) + within_m - self._low) / OUTLINE_CELL_M)
        c0, r0 = (max(0, int(v)) for v in low)
        c1, r1 = min(self._columns - 1, int(high[0])), min(self._rows - 1, int(high[1]))
        if c0 > c1 or r0 > r1:
            return np.empty((0, 2))
        rows = range(r0 * self._columns, r1 * self._columns + 1, self._columns)
        runs = [self._points[self._first[r + c0] : self._first[r + c1 + 1]] for r in rows]
        return np.ascontiguousarray(np.concatenate(runs))

    def distances_m(self, poses: np.ndarray, reach_m: float) -> np.ndarray:
        """(N, T) metres along each trajectory from each true pose (N, 3) to its collision
        point; inf where there is none within `reach_m` of the pose (set it where labels stop
        changing, core.labels.label_reach_m: nothing farther changes one)."""
        poses = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
        found = np.empty((len(poses), len(self._curvatures)))  # (N, T) metres
        for i, pose in enumerate(poses):
            found[i] = self.view_distances_m(pose[0], pose[1], pose[2:3], reach_m)[0]
        return found

    def view_distances_m(
        self, x: float, y: float, headings: np.ndarray, reach_m: float
    ) -> np.ndarray:
        """(V, T) metres: distances_m from (x, y) facing each of `headings` (V,) rad, with the
        outline near the place gathered once for them all."""
        from tvl_cli.core.contacts_kernel import first_contacts_in_windows  # compiled

        near = self._near(x, y, reach_m + self._body_radius_m)
        # Nearest first, so that each view stops at the first point too far to be met sooner
        # than what it found: one ordering serves every view, all from the same place.
        offset = near - np.array([x, y])
        near = np.ascontiguousarray(near[np.argsort(np.einsum("ij,ij->i", offset, offset))])
        poses = np.stack([np.full(len(headings), x), np.full(len(headings), y), headings], 1)
        found = np.empty((len(headings), len(self._curvatures)))
        views = len(headings)
        first_contacts_in_windows(
            np.ascontiguousarray(poses),
            self._curvatures,
            near,
            np.zeros(views, np.int64),
            np.full(views, len(near), np.int64),
            self._body_radius_m,
            reach_m,
            True,
            found,
        )
        found[found > reach_m] = math.inf
        return found

    def velocities_mps(
        self, distances_m: np.ndarray, decel_mps2: float, margin_m: float
    ) -> np.ndarray:
        """(N, T) m/s: the labels of collision points (N, T) metres, as core.labels makes them."""
        v_max = np.array(self._robot.v_max_mps)
        return velocity_labels(distances_m, v_max, decel_mps2, margin_m)
