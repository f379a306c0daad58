"""The places an exploring robot knows, for the novelty rule (agent.explore_rules): the pairs
that lead to places the robot does not know.

Places are judged by the robot alone, as a real one could: from where its odometry has been,
in square bins, and from the echoes of its sonar ring now. A (rotation, trajectory) pair
leads to the bins its arc passes within a look-ahead, before the first point an echo blocks;
it leads somewhere new when one of them is neither visited nor aimed at before. The paper
(§5.2) found that the least experienced choice kept the robot in small parts of cluttered
worlds, and hoped for choices made on "unfamiliar environment regions".
"""

from __future__ import annotations

import math

import numpy as np

from tvl_cli.agent.policy import Pose
from tvl_cli.core.robot_config import RobotConfig

# Two body widths and a little more: small enough that a room holds many, large enough that
# odometry drift (tens of centimetres over 45 simulated minutes in the lab) seldom moves the
# robot's idea of where it has been by a whole bin.
NOVELTY_BIN_M = 0.5
# How far along each arc new ground is looked for: T0's braking horizon with the default
# labels (v_max² / 2a + margin = 1.95 m), beyond which the ring's echoes say little.
NOVELTY_LOOKAHEAD_M = 2.0
# Spacing of the points tested along each arc: a fifth of a bin, so no bin an arc crosses is
# missed by more than a corner.
ARC_STEP_M = 0.1
# An echo nearer than this to the body's edge, beyond where the learner stops short of what
# it closes in on (`near_m`), blocks the way at a point of an arc: the sonar's own noise
# (about 1 cm) and a few centimetres to spare.
BLOCKED_BEYOND_STOP_M = 0.05
# Where across its cone an echo may have come from, as fractions of the cone's width: a
# sonar tells the range of the nearest surface, not its bearing within the cone.
ECHO_SPREAD = (-0.5, 0.0, 0.5)


class Places:
    """The odometry bins the robot knows, and the pairs that lead to bins it does not."""

    def __init__(self, robot: RobotConfig, stop_m: float) -> None:
        """`stop_m`: how far short of what it closes in on the learner stops (`near_m`)."""
        self.robot = robot
        # An arc's point is out of reach with an echo this near its centre.
        self._blocked_m = robot.radius_m + stop_m + BLOCKED_BEYOND_STOP_M
        self._known: set[tuple[int, int]] = set()  # bins visited, or aimed at
        count = robot.sonar.count
        steps = round(NOVELTY_LOOKAHEAD_M / ARC_STEP_M)
        along = ARC_STEP_M * np.arange(1, steps + 1)  # (K,) metres
        arcs = np.stack([_arc_points(t.curvature_per_m, along) for t in robot.trajectories])
        # (count, 7, K, 2) metres: every pair's arc in the robot's frame, after the spin.
        turns = 2 * math.pi * np.arange(count) / count  # (count,) radians CCW
        self._arcs = np.einsum("rij,tkj->rtki", _rotations(turns), arcs)
        spread = math.radians(robot.sonar.cone_deg) * np.array(ECHO_SPREAD)  # (S,) radians
        bearings = (turns[:, None] + spread[None, :]).ravel()  # (count * S,) radians
        self._echo_directions = np.stack([np.cos(bearings), np.sin(bearings)], axis=1)
        self._spread = len(ECHO_SPREAD)
        # The last judgement: each point's bin (count, 7, K, 2) and whether it is in reach.
        self._bins = np.zeros((count, len(robot.trajectories), len(along), 2), dtype=np.int64)
        self._reach = np.zeros(self._bins.shape[:-1], dtype=bool)

    def visit(self, odometry: Pose) -> None:
        """The robot's odometry says it is here now. Every bin its body overlaps is known, so
        a place beside a wall, where the centre never goes, is known once the robot has been
        alongside."""
        x, y, _ = odometry
        body = self.robot.radius_m
        bx, by = math.floor(x / NOVELTY_BIN_M), math.floor(y / NOVELTY_BIN_M)
        for cx in (bx - 1, bx, bx + 1):
            for cy in (by - 1, by, by + 1):
                # The nearest point of the bin's square to the centre.
                nx = min(max(x, cx * NOVELTY_BIN_M), (cx + 1) * NOVELTY_BIN_M)
                ny = min(max(y, cy * NOVELTY_BIN_M), (cy + 1) * NOVELTY_BIN_M)
                if math.hypot(x - nx, y - ny) < body:
                    self._known.add((cx, cy))

    def leading_to_new(self, ring_m: np.ndarray, odometry: Pose) -> np.ndarray:
        """(count, 7) bool: the pairs whose arc reaches a bin not known, before the first
        point an echo of `ring_m` (16,) metres blocks."""
        body = self.robot.radius_m
        # (count * S, 2) metres: each sonar's echo, at its range from the body's edge. A sonar
        # that heard nothing reads its maximum range, beyond every arc's reach.
        echoes = self._echo_directions * (body + np.repeat(ring_m, self._spread))[:, None]
        arcs = self._arcs  # (count, 7, K, 2) metres
        gaps = np.linalg.norm(arcs[..., None, :] - echoes, axis=-1)  # (count, 7, K, E)
        self._reach = np.logical_and.accumulate(gaps.min(axis=-1) >= self._blocked_m, axis=2)
        x, y, heading = odometry
        world = arcs @ _rotations(np.array([heading]))[0].T + (x, y)  # (count, 7, K, 2)
        self._bins = np.floor(world / NOVELTY_BIN_M).astype(np.int64)
        new = np.array(
            [(bx, by) not in self._known for bx, by in self._bins.reshape(-1, 2).tolist()]
        ).reshape(self._reach.shape)
        return np.any(new & self._reach, axis=2)

    def aim(self, rotation: int, trajectory: int) -> None:
        """The robot sets off along this pair, as `leading_to_new` judged it last: the bins
        it leads to are known from now on, reached or not. A place the robot fails to reach
        (through a gap narrower than its echoes made it look) so pulls it once, instead of
        holding it at the threshold."""
        reached = self._bins[rotation, trajectory][self._reach[rotation, trajectory]]
        self._known.update((bx, by) for bx, by in reached.tolist())


def _arc_points(curvature_per_m: float, along_m: np.ndarray) -> np.ndarray:
    """(K, 2) metres: points at these arc lengths along a trajectory leaving the origin along
    +x, turning left for positive curvature."""
    if curvature_per_m == 0:
        return np.stack([along_m, np.zeros_like(along_m)], axis=1)
    turned = curvature_per_m * along_m  # (K,) radians
    return np.stack([np.sin(turned), 1.0 - np.cos(turned)], axis=1) / curvature_per_m


def _rotations(angles_rad: np.ndarray) -> np.ndarray:
    """(n, 2, 2) matrices turning a column vector CCW by each angle."""
    c, s = np.cos(angles_rad), np.sin(angles_rad)
    return np.stack([np.stack([c, -s], axis=-1), np.stack([s, c], axis=-1)], axis=-2)
