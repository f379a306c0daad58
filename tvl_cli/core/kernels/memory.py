"""The echo memory's cast: the nearest remembered surface in each beam (core.memory).

`remembered_ranges` is compiled; `memory_reference` computes the same in numpy, for the
tests to hold the kernel to.

Arguments, for B beams of `rays_per_beam` rays each and a memory of K echoes:
    origins (B * rays, 2), directions (B * rays, 2): each ray's transducer (metres) and unit
        direction, beam by beam;
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
    out[:] = np.inf
    for r in range(origins.shape[0]):
        ox, oy = origins[r, 0], origins[r, 1]
        dx, dy = directions[r, 0], directions[r, 1]
        best = np.inf
        for k in range(centres.shape[0]):
            if heard[k] < since:
                continue
            ax, ay = axes[k, 0], axes[k, 1]
            facing = dx * ax + dy * ay
            if facing <= 0.0:
                continue
            cx, cy = centres[k, 0], centres[k, 1]
            t = ((cx - ox) * ax + (cy - oy) * ay) / facing
            if t < 0.0 or t >= best:
                continue
            across = -((ox + t * dx) - cx) * ay + ((oy + t * dy) - cy) * ax
            if abs(across) <= half_widths[k]:
                best = t
        b = r // rays_per_beam
        if best < out[b]:
            out[b] = best
