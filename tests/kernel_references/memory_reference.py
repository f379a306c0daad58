"""The echo memory's kernels in plain numpy: what `agent.memory_kernel.remember_echoes`
and `agent.memory_kernel.remembered_ranges` compute (the cast every ray against every echo at
once), kept for the tests that compare them. Same arguments, same results."""

from __future__ import annotations

import math

import numpy as np

from tvl_cli.core.memory import POINTS


def remember_echoes_reference(
    origins: np.ndarray,
    directions: np.ndarray,
    rays_per_beam: int,
    ring_m: np.ndarray,
    max_range_m: float,
    range_m: float,
    tan_half_cone: float,
    half_patch_m: float,
    step: int,
    centres: np.ndarray,
    axes: np.ndarray,
    half_widths: np.ndarray,
    heard: np.ndarray,
    next_slot: int,
) -> int:
    """remember_echoes in numpy."""
    beams = np.flatnonzero((ring_m < max_range_m) & (ring_m <= range_m))
    axis_rows = beams * rays_per_beam + rays_per_beam // 2
    beam_axes = directions[axis_rows]  # (h, 2)
    ranges = ring_m[beams]  # (h,) metres
    slots = (next_slot + np.arange(len(beams))) % len(heard)
    centres[slots] = origins[axis_rows] + ranges[:, None] * beam_axes
    axes[slots] = beam_axes
    half_widths[slots] = np.maximum(half_patch_m, ranges * tan_half_cone)
    heard[slots] = step
    return int((next_slot + len(beams)) % len(heard))


def remembered_ranges_reference(
    kind: str,
    origins: np.ndarray,
    directions: np.ndarray,
    rays_per_beam: int,
    half_cone_rad: float,
    centres: np.ndarray,
    axes: np.ndarray,
    half_widths: np.ndarray,
    heard: np.ndarray,
    since: int,
    within_m: np.ndarray | None = None,
    cleared_above_m: np.ndarray | None = None,
) -> np.ndarray:
    """remembered_ranges in numpy: every ray against every echo at once."""
    beams = len(origins) // rays_per_beam
    if cleared_above_m is not None and np.isfinite(cleared_above_m).any():
        # Cast once for each limit the beams have, against the echoes narrow enough for it
        # (the rest as if forgotten), and each beam takes the cast of its own limit.
        ranges = np.full(beams, np.inf)
        for limit in np.unique(cleared_above_m):
            narrow_heard = np.where(half_widths <= limit, heard, since - 1)
            cast = remembered_ranges_reference(
                kind, origins, directions, rays_per_beam, half_cone_rad, centres, axes,
                half_widths, narrow_heard, since, within_m,
            )  # fmt: skip
            ranges = np.where(cleared_above_m == limit, cast, ranges)
        return ranges
    live = heard >= since
    centres, axes, half_widths = centres[live], axes[live], half_widths[live]
    if len(centres) == 0:
        return np.full(beams, np.inf)
    if kind == POINTS:
        middle = rays_per_beam // 2
        origin = origins[middle::rays_per_beam]  # (B, 2) metres
        axis = directions[middle::rays_per_beam]  # (B, 2) unit vectors
        offset = centres[None, :, :] - origin[:, None, :]  # (B, K, 2) metres
        distance = np.hypot(offset[..., 0], offset[..., 1])  # (B, K) metres
        along = offset[..., 0] * axis[:, None, 0] + offset[..., 1] * axis[:, None, 1]
        inside = (along >= distance * math.cos(half_cone_rad)) & (distance > 0.0)
        return _within(np.where(inside, distance, np.inf).min(axis=1), within_m)
    facing = directions @ axes.T  # (R, K) D . axis
    to_centre = centres[None, :, :] - origins[:, None, :]  # (R, K, 2) metres
    depth = to_centre[..., 0] * axes[:, 0] + to_centre[..., 1] * axes[:, 1]  # (R, K) metres
    with np.errstate(divide="ignore", invalid="ignore"):
        t = depth / facing  # (R, K) metres along each ray
    hit_x = origins[:, None, 0] + t * directions[:, None, 0] - centres[:, 0]  # (R, K) metres
    hit_y = origins[:, None, 1] + t * directions[:, None, 1] - centres[:, 1]
    across = -hit_x * axes[:, 1] + hit_y * axes[:, 0]  # (R, K) metres along each patch
    met = (facing > 0.0) & (t >= 0.0) & (np.abs(across) <= half_widths)
    nearest = np.where(met, t, np.inf).min(axis=1).reshape(beams, rays_per_beam).min(axis=1)
    return _within(nearest, within_m)


def _within(ranges_m: np.ndarray, within_m: np.ndarray | None) -> np.ndarray:
    """inf for each beam's range no nearer than its `within_m` (None: any is near enough)."""
    return ranges_m if within_m is None else np.where(ranges_m < within_m, ranges_m, np.inf)
