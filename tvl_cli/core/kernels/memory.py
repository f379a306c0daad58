"""The echo memory's cast: the nearest remembered surface in each beam (core.memory).

`remembered_ranges` is compiled; `memory_reference` computes the same in numpy, for the
tests to hold the kernel to.

Arguments, for B beams of `rays_per_beam` rays each and a memory of K echoes:
    origins (B * rays, 2), directions (B * rays, 2): each ray's transducer (metres; a
        beam's rays share one) and unit direction, beam by beam;
    centres (K, 2) metres: each echo point; axes (K, 2): the unit beam axis it was heard
        along; half_widths (K,) metres: the half width of its patch;
    heard (K,): the control step each was heard on; `since`: the oldest step remembered.
It returns (B,) metres from each transducer to the nearest remembered surface in the beam,
inf where there is none.

A point is met by a beam when it lies inside the cone about the beam's middle ray. A patch is
the segment centre +/- w * (-ay, ax): a ray O + tD meets its line where
(O + tD - centre) . axis = 0, i.e. t = (centre - O) . axis / (D . axis), and hears it only
from the side that faced the transducer which heard it (D . axis > 0).
"""

from __future__ import annotations

import math

import numpy as np

from tvl_cli.core.kernels import kernel
from tvl_cli.core.memory import POINTS

# Metres of slack in the wedge test, far above rounding and far below any patch.
WEDGE_SLACK_M = 1e-9


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
) -> np.ndarray:
    """(B,) metres: the nearest remembered point (kind `points`) or patch in each beam."""
    beams = len(origins) // rays_per_beam
    out = np.empty(beams)  # (B,) metres
    if kind == POINTS:
        _points_in_cones(
            origins, directions, rays_per_beam, math.cos(half_cone_rad), centres, heard, since, out
        )
    else:
        _patches_met(
            origins, directions, rays_per_beam, centres, axes, half_widths, heard, since, out
        )
    return out


@kernel
def _points_in_cones(
    origins, directions, rays_per_beam, cos_half_cone, centres, heard, since, out
):  # fmt: skip
    middle = rays_per_beam // 2
    for b in range(out.shape[0]):
        ray = b * rays_per_beam + middle
        ox, oy = origins[ray, 0], origins[ray, 1]
        ax, ay = directions[ray, 0], directions[ray, 1]
        best = np.inf
        for k in range(centres.shape[0]):
            if heard[k] < since:
                continue
            dx, dy = centres[k, 0] - ox, centres[k, 1] - oy
            distance = math.sqrt(dx * dx + dy * dy)
            if 0.0 < distance < best and dx * ax + dy * ay >= distance * cos_half_cone:
                best = distance
        out[b] = best


@kernel
def _patches_met(
    origins, directions, rays_per_beam, centres, axes, half_widths, heard, since, out
):  # fmt: skip
    middle = rays_per_beam // 2
    for b in range(out.shape[0]):
        first = b * rays_per_beam
        # Every ray of a beam leaves one transducer within `spread` of the middle ray, so a
        # patch no nearer than its half width to that wedge meets none of them; skipping it
        # saves most of the work and changes no reading.
        ox, oy = origins[first, 0], origins[first, 1]
        mx, my = directions[first + middle, 0], directions[first + middle, 1]
        cos_spread = 1.0
        for r in range(first, first + rays_per_beam):
            cos_ray = directions[r, 0] * mx + directions[r, 1] * my
            if cos_ray < cos_spread:
                cos_spread = cos_ray
        sin_spread = math.sqrt(1.0 - cos_spread * cos_spread) if cos_spread < 1.0 else 0.0
        best = np.inf
        for k in range(centres.shape[0]):
            if heard[k] < since:
                continue
            cx, cy = centres[k, 0], centres[k, 1]
            vx, vy = cx - ox, cy - oy
            along = vx * mx + vy * my
            lateral = abs(vx * my - vy * mx)
            reach = half_widths[k] + WEDGE_SLACK_M
            if along <= 0.0:
                if vx * vx + vy * vy > reach * reach:
                    continue
            elif lateral * cos_spread - along * sin_spread > reach or along - reach >= best:
                continue  # outside the wedge, or no nearer than what the beam already met
            ax, ay = axes[k, 0], axes[k, 1]
            ahead = vx * ax + vy * ay  # the transducer's distance behind the patch's line
            if ahead < 0.0:
                continue  # the transducer is on the far side: it cannot hear the patch
            offset = vx * ay - vy * ax  # where across the patch the transducer stands
            for r in range(first, first + rays_per_beam):
                dx, dy = directions[r, 0], directions[r, 1]
                facing = dx * ax + dy * ay
                if facing <= 0.0 or ahead >= best * facing:
                    continue
                # The ray meets the line at t = ahead / facing, (offset + t * slant) across
                # the patch; compared times `facing`, so that only a hit costs a division.
                slant = dy * ax - dx * ay
                if abs(offset * facing + ahead * slant) <= half_widths[k] * facing:
                    best = ahead / facing
        out[b] = best
