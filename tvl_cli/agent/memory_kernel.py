"""The echo memory's kernels (core.memory): keeping a reading's echoes, and the cast, the
nearest remembered surface in each beam.

`remember_echoes` and `remembered_ranges` are compiled; `memory_reference`
(tests/kernel_references/) computes the same in numpy, for the tests to hold the kernels to.

The arguments they share, for B beams of `rays_per_beam` rays each and a memory of K
echoes:
    origins (B * rays, 2), directions (B * rays, 2): each ray's transducer (metres; a
        beam's rays share one) and unit direction, beam by beam;
    centres (K, 2) metres: each echo point; axes (K, 2): the unit beam axis it was heard
        along; half_widths (K,) metres: the half width of its patch;
    heard (K,): the control step each was heard on.
The cast's `since` is the oldest step remembered, and `within_m` (B,) metres how far to look
in each beam (its live reading: nothing farther changes what the robot perceives); each beam
meets only the echoes no wider than its `cleared_above_m` (B,) metres either side (inf: every
echo; core.memory, *clearing*). It returns (B,) metres from each transducer to the nearest
remembered surface in the beam nearer than that, inf where there is none.

A point is met by a beam when it lies inside the cone about the beam's middle ray. A patch is
the segment centre +/- w * (-ay, ax): a ray O + tD meets its line where
(O + tD - centre) . axis = 0, i.e. t = (centre - O) . axis / (D . axis), and hears it only
from the side that faced the transducer which heard it (D . axis > 0).
"""

from __future__ import annotations

import math

import numpy as np

from tvl_cli.core.memory import POINTS
from tvl_cli.core.numba_kernel import inlined, kernel

# Metres of slack in the wedge test, far above rounding and far below any patch.
WEDGE_SLACK_M = 1e-9
# A little above the largest product of two unit vectors that rounding can give.
FACING_MAX = 1.000001


@kernel
def remember_echoes(
    origins, directions, rays_per_beam, ring_m, max_range_m, range_m, tan_half_cone,
    half_patch_m, step, centres, axes, half_widths, heard, next_slot,
):  # fmt: skip
    """Keep the echoes of one reading, ring_m (B,) metres along beams whose rays are origins
    and directions (as above), in the memory's ring buffer (centres, axes, half_widths,
    heard: K slots) from slot next_slot on, each as heard on control step `step`; the next
    free slot. A beam that heard nothing (the maximum range), or farther than range_m, keeps
    nothing; a patch is as wide as the beam there (range * tan_half_cone either side), at
    least half_patch_m either side."""
    middle = rays_per_beam // 2
    capacity = heard.shape[0]
    for b in range(ring_m.shape[0]):
        range_read = ring_m[b]
        if not (range_read < max_range_m and range_read <= range_m):
            continue
        row = b * rays_per_beam + middle
        ax, ay = directions[row, 0], directions[row, 1]
        centres[next_slot, 0] = origins[row, 0] + range_read * ax
        centres[next_slot, 1] = origins[row, 1] + range_read * ay
        axes[next_slot, 0], axes[next_slot, 1] = ax, ay
        half_width = range_read * tan_half_cone
        if half_width < half_patch_m:
            half_width = half_patch_m
        half_widths[next_slot] = half_width
        heard[next_slot] = step
        next_slot = (next_slot + 1) % capacity
    return next_slot


def remembered_ranges(
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
    """(B,) metres: the nearest remembered point (kind `points`) or patch in each beam
    nearer than within_m (B,) (None: at any range), of those no wider than the beam's
    cleared_above_m (B,) either side (None: every one); inf where there is none."""
    beams = len(origins) // rays_per_beam
    if within_m is None:
        within_m = np.full(beams, np.inf)
    if cleared_above_m is None:
        cleared_above_m = np.full(beams, np.inf)
    out = np.empty(beams)  # (B,) metres
    if kind == POINTS:
        _points_in_cones(
            origins,
            directions,
            rays_per_beam,
            math.cos(half_cone_rad),
            centres,
            half_widths,
            heard,
            since,
            within_m,
            cleared_above_m,
            out,
        )
    else:
        _patches_met(
            origins,
            directions,
            rays_per_beam,
            centres,
            axes,
            half_widths,
            heard,
            since,
            within_m,
            cleared_above_m,
            out,
        )
    return out


@kernel
def _points_in_cones(
    origins, directions, rays_per_beam, cos_half_cone, centres, half_widths, heard, since,
    within_m, cleared_above_m, out,
):  # fmt: skip
    middle = rays_per_beam // 2
    for b in range(out.shape[0]):
        ray = b * rays_per_beam + middle
        ox, oy = origins[ray, 0], origins[ray, 1]
        ax, ay = directions[ray, 0], directions[ray, 1]
        best = within_m[b]
        for k in range(centres.shape[0]):
            if heard[k] < since or half_widths[k] > cleared_above_m[b]:
                continue
            dx, dy = centres[k, 0] - ox, centres[k, 1] - oy
            distance = math.sqrt(dx * dx + dy * dy)
            if 0.0 < distance < best and dx * ax + dy * ay >= distance * cos_half_cone:
                best = distance
        out[b] = best if best < within_m[b] else np.inf


@kernel
def _patches_met(
    origins, directions, rays_per_beam, centres, axes, half_widths, heard, since, within_m,
    cleared_above_m, out,
):  # fmt: skip
    beams = out.shape[0]
    wedges = _beam_wedges(origins, directions, rays_per_beam, beams)
    for b in range(beams):
        out[b] = within_m[b]  # the nearest met so far
    # Echo by echo, each against every beam: each beam still meets the echoes in their
    # order, and the cuts skip only what could not come nearer than the beam's best. The
    # cuts are taken for all beams at once, free of branches, and only the beams they leave
    # are cast against the patch's rays (the patch's depth and offset kept for them).
    skipped = np.empty(beams, dtype=np.bool_)
    depth, offsets = np.empty(beams), np.empty(beams)
    for k in range(centres.shape[0]):
        if heard[k] < since:
            continue
        _cut_beams(
            k, centres, axes, half_widths, cleared_above_m, wedges, out, skipped, depth,
            offsets,
        )  # fmt: skip
        _cast_patch(k, axes, half_widths, directions, rays_per_beam, skipped, depth, offsets, out)
    for b in range(beams):
        if out[b] >= within_m[b]:
            out[b] = np.inf


@inlined
def _beam_wedges(origins, directions, rays_per_beam, beams):
    """Each beam's wedge (B,) x 6: its transducer (ox, oy) metres, the unit middle ray (mx,
    my), and the cosine and sine of the widest angle of its rays from the middle one."""
    # Each beam's rays leave one transducer within that spread of the middle ray: a patch no
    # nearer than its half width to the wedge meets none of them.
    middle = rays_per_beam // 2
    ox, oy = np.empty(beams), np.empty(beams)
    mx, my = np.empty(beams), np.empty(beams)
    cos_spread, sin_spread = np.empty(beams), np.empty(beams)
    for b in range(beams):
        first = b * rays_per_beam
        ox[b], oy[b] = origins[first, 0], origins[first, 1]
        mx[b], my[b] = directions[first + middle, 0], directions[first + middle, 1]
        cos_b = 1.0
        for r in range(first, first + rays_per_beam):
            cos_ray = directions[r, 0] * mx[b] + directions[r, 1] * my[b]
            if cos_ray < cos_b:
                cos_b = cos_ray
        cos_spread[b] = cos_b
        sin_spread[b] = math.sqrt(1.0 - cos_b * cos_b) if cos_b < 1.0 else 0.0
    return ox, oy, mx, my, cos_spread, sin_spread


@inlined
def _cut_beams(
    k, centres, axes, half_widths, cleared_above_m, wedges, out, skipped, depth, offsets,
):  # fmt: skip
    """Mark in skipped (B,) the beams patch k cannot come nearer in than what they met so far
    (out), keeping for the others the transducer's depth behind the patch's line and offset
    across it (metres)."""
    ox, oy, mx, my, cos_spread, sin_spread = wedges
    cx, cy = centres[k, 0], centres[k, 1]
    reach = half_widths[k] + WEDGE_SLACK_M
    ax, ay = axes[k, 0], axes[k, 1]
    for b in range(out.shape[0]):
        best = out[b]
        vx, vy = cx - ox[b], cy - oy[b]
        ahead = vx * ax + vy * ay  # the transducer's distance behind the patch's line
        depth[b] = ahead
        offsets[b] = vx * ay - vy * ax  # where across the patch the transducer stands
        along = vx * mx[b] + vy * my[b]
        lateral = abs(vx * my[b] - vy * mx[b])
        behind = along <= 0.0
        # On the far side it cannot hear the patch; and no ray meets the line nearer than
        # `ahead` (facing is at most 1, give or take rounding). Behind the transducer, only
        # a patch reaching it; ahead, one outside the wedge, or no nearer than what the beam
        # already met, is skipped.
        skipped[b] = (
            (half_widths[k] > cleared_above_m[b])
            | (ahead < 0.0)
            | (ahead >= best * FACING_MAX)
            | (behind & (vx * vx + vy * vy > reach * reach))
            | (
                ~behind
                & (
                    (lateral * cos_spread[b] - along * sin_spread[b] > reach)
                    | (along - reach >= best)
                )
            )
        )


@inlined
def _cast_patch(k, axes, half_widths, directions, rays_per_beam, skipped, depth, offsets, out):
    """Cast the rays of each beam not skipped against patch k, keeping in out (B,) metres the
    nearer of what the beam met before and where a ray meets the patch."""
    ax, ay = axes[k, 0], axes[k, 1]
    half_width = half_widths[k]
    for b in range(out.shape[0]):
        if skipped[b]:
            continue
        best, ahead, offset = out[b], depth[b], offsets[b]
        first = b * rays_per_beam
        for r in range(first, first + rays_per_beam):
            dx, dy = directions[r, 0], directions[r, 1]
            facing = dx * ax + dy * ay
            if facing <= 0.0 or ahead >= best * facing:
                continue
            # The ray meets the line at t = ahead / facing, (offset + t * slant) across the
            # patch; compared times `facing`, so that only a hit costs a division.
            slant = dy * ax - dx * ay
            if abs(offset * facing + ahead * slant) <= half_width * facing:
                best = ahead / facing
        out[b] = best
