"""The sonar ring cast in plain numpy, every ray of a robot at once against every wall: what
`sim.ring_kernel.ring_ranges` computes, kept for the tests that compare the two. Same
arguments, same results: the kernel asks only the walls of the cells each ray crosses, this
asks them all, so the two agree only if the grid never leaves out a wall that decides a reading."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def ring_ranges_reference(
    poses: np.ndarray,
    noise: np.ndarray,
    layout: tuple[np.ndarray, np.ndarray],
    walls: tuple[np.ndarray, ...],
    grid: tuple[object, ...],
    reach_m: float,
    discs: np.ndarray,
    rings: np.ndarray,
    rings_rough: np.ndarray,
    model: tuple[float | bool, ...],
    readings: np.ndarray,
    sources: np.ndarray,
) -> None:
    """Fill readings (N, 16) with metres and sources (N, 16) with obstacles, as
    ring.ring_ranges (which documents the arguments; the grid and the reach go unused)."""
    first_disc = len(walls[3])
    numbers = (np.arange(first_disc), first_disc, first_disc + len(discs))
    for robot, pose in enumerate(poses):
        readings[robot], sources[robot] = _read(
            pose, noise[robot], layout, walls, discs, rings, rings_rough, model, numbers
        )


def _read(
    pose: np.ndarray,
    noise: np.ndarray,
    layout: tuple[np.ndarray, np.ndarray],
    walls: tuple[np.ndarray, ...],
    discs: np.ndarray,
    rings: np.ndarray,
    rings_rough: np.ndarray,
    model: tuple[float | bool, ...],
    numbers: tuple[np.ndarray, int, int],
) -> tuple[np.ndarray, np.ndarray]:
    """(16,) metres read by one robot, and (16,) the obstacle each beam heard; `numbers`:
    the robot's walls' own numbers, and those of the first disc and the first ring wall."""
    max_range_m, min_range_m, noise_sigma_m, noise_fraction, ideal = model[6:]
    count = len(layout[0])
    rays = _world_rays(pose, layout, float(model[0]))
    wall_numbers, first_disc, first_ring = numbers
    with np.errstate(divide="ignore", invalid="ignore"):
        found = []  # (hit, echo, source) triples, each (16 * rays,)
        if len(walls[3]):
            hit, echo, k = _segments(walls, rays, model)
            found.append((hit, echo, wall_numbers.take(k)))
        if len(discs):
            hit, echo, k = _circles(discs, np.zeros(len(discs)), rays, model, solid=True)
            found.append((hit, echo, first_disc + k))
        if len(rings):
            hit, echo, k = _circles(rings, rings_rough, rays, model, solid=False)
            found.append((hit, echo, first_ring + k))
        if not found:
            return np.full(count, max_range_m), np.full(count, -1)
        hit, echo, source = found[0]
        for other_hit, other_echo, other_source in found[1:]:
            # Where a ray meets this kind of surface first, its echo is this surface's.
            first = other_hit < hit
            echo = np.where(first, other_echo, echo)
            source = np.where(first, other_source, source)
            hit = np.minimum(hit, other_hit)
        per_beam = echo.reshape(count, -1)  # (16, rays) metres
        ray = per_beam.argmin(axis=1)  # (16,) each beam's nearest echo, the first of equals
        nearest = per_beam[np.arange(count), ray]  # (16,) metres; inf: no echo
        heard = nearest <= max_range_m
        if not ideal:
            sigma = noise_sigma_m + noise_fraction * nearest
            nearest = nearest + sigma * noise
        measured = np.minimum(np.maximum(nearest, min_range_m), max_range_m)
    heard_from = source.reshape(count, -1)[np.arange(count), ray]
    return np.where(heard, measured, max_range_m), np.where(heard, heard_from, -1)


@dataclass(frozen=True, slots=True, eq=False)
class _Rays:
    """One reading's rays in the world frame, as row vectors."""

    origin: np.ndarray  # (16, 2) transducer positions, metres
    origin_of_ray: np.ndarray  # (16 * rays, 1, 2) each ray's transducer position, metres
    direction: np.ndarray  # (16 * rays, 2) unit vectors, beam by beam
    direction_perp: np.ndarray  # (16 * rays, 2) (dy, -dx)
    along: np.ndarray  # (16 * rays,) D.O, metres
    across: np.ndarray  # (16 * rays,) cross(O, D), metres


def _world_rays(
    pose: np.ndarray, layout: tuple[np.ndarray, np.ndarray], body_radius_m: float
) -> _Rays:
    transducers, ray_table = layout
    x, y, theta = pose
    cos_t, sin_t = np.cos(theta), np.sin(theta)
    turn = np.array([[cos_t, sin_t], [-sin_t, cos_t]])  # row vector @ turn: body -> world
    centre = np.array([x, y])  # (2,) metres
    # The transducers' outward normals U, the rays' directions D and the perpendiculars
    # (dy, -dx) of those directions, turned to the pose in one small matrix product.
    body = np.concatenate(
        [transducers, ray_table[:, :2], np.stack([ray_table[:, 1], -ray_table[:, 0]], axis=1)]
    )
    vectors = body @ turn
    count, rays = len(transducers), len(ray_table)
    direction_both = vectors[count:]  # (2 * 16 * rays, 2) D, then (dy, -dx)
    # From the transducer at P + rU a ray at offset d from U has D.O = D.P + r cos(d) and
    # cross(O, D) = cross(P, D) + r sin(d).
    origin_terms = direction_both @ centre + np.concatenate([ray_table[:, 2], ray_table[:, 3]])
    origin = centre + body_radius_m * vectors[:count]  # (16, 2) metres
    beam_of_ray = np.arange(rays) // (rays // count)
    return _Rays(
        origin=origin,
        origin_of_ray=origin.take(beam_of_ray, axis=0)[:, None, :],
        direction=direction_both[:rays],
        direction_perp=direction_both[rays:],
        along=origin_terms[:rays],
        across=origin_terms[rays:],
    )


def _first(t: np.ndarray, valid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per ray, the flat index of its nearest valid crossing in t (16 * rays, n), and its t."""
    np.putmask(t, ~valid, np.inf)
    n = t.shape[1]
    flat = np.arange(len(t)) * n + t.argmin(axis=1)  # (16 * rays,)
    return flat, t.take(flat)


def _segments(
    walls: tuple[np.ndarray, ...], rays: _Rays, model: tuple[float | bool, ...]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(hit, echo) metres for every ray against its nearest wall segment, and that segment."""
    start, normal, moment, length_m, ends, corner_sides, roughness = walls
    _, behind_m, cos_specular, corner_slope, corner_min_radius_m, edge_echo_range_m = model[:6]
    max_range_m, ideal = model[6], model[10]
    # Ray O + tD meets segment A + sE where t = cross(A-O, E) / cross(D, E) and
    # s = cross(A-O, D) / cross(D, E); |cross(D, E)| / |E| is the cosine of incidence.
    # Each cross product splits into a matrix product and a per-ray or per-wall term.
    count, n, ray_count = len(rays.origin), len(length_m), len(rays.direction)
    denom = rays.direction @ normal  # (16 * rays, n) cross(D, E)
    t_num = moment - rays.origin @ normal  # (16, n) cross(A - O, E)
    s_num = rays.direction_perp @ start - rays.across[:, None]  # cross(A - O, D)
    t = (t_num[:, None, :] / denom.reshape(count, -1, n)).reshape(ray_count, n)  # metres
    s = s_num / denom  # (16 * rays, n) fraction along each segment
    flat, hit = _first(t, (t > -behind_m) & (s >= 0.0) & (s <= 1.0))
    k = flat % n  # (16 * rays,) the wall each ray meets first
    if ideal:
        return hit, hit, k
    cross = denom.take(flat)
    length = length_m.take(k)
    cos_incidence = np.abs(cross) / length
    specular = (cos_incidence >= cos_specular) | (hit <= 0.0)
    # For a forward hit the transducer is on the side of the wall given by the sign of
    # cross(D, E); a corner is concave when the other wall leaves it on that same side,
    # and an edge when it leaves on the other side or no wall meets it there.
    gap = np.abs(s.take(flat)[:, None] - np.array([0.0, 1.0])) * length[:, None]  # (., 2)
    reach = np.maximum(corner_min_radius_m, corner_slope * hit)  # metres
    # A ray that meets no wall has no wall to judge a corner on: argmin named wall 0
    # for it, and an infinite reach would make that wall's corners echo.
    near_end = (gap <= reach[:, None]) & np.isfinite(hit)[:, None]  # (16 * rays, 2)
    side = corner_sides.take(k, axis=0) * cross[:, None]  # (16 * rays, 2)
    to_corner = ends.take(k, axis=0) - rays.origin_of_ray  # (16 * rays, 2, 2) metres
    corner_m = np.hypot(to_corner[..., 0], to_corner[..., 1])  # (16 * rays, 2) metres
    heard = (side > 0.0) | (corner_m <= edge_echo_range_m)
    corner = np.where(near_end & heard, corner_m, np.inf).min(axis=1)
    rough = roughness.take(k)
    diffuse_m = max_range_m * np.sqrt(rough * cos_incidence)
    corner = np.minimum(corner, np.where((rough > 0.0) & (hit <= diffuse_m), hit, np.inf))
    return hit, np.where(specular, hit, corner), k


def _circles(
    circles: np.ndarray,
    roughness: np.ndarray,
    rays: _Rays,
    model: tuple[float | bool, ...],
    solid: bool,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(hit, echo) metres for every ray against its nearest disc (solid) or ring wall of the
    given roughness (a disc always echoes), and the circle each ray meets first."""
    behind_m, cos_specular, max_range_m, ideal = model[1], model[2], model[6], model[10]
    # |O + tD - C| = r at t = b -/+ h: b = D.(C - O) is where the ray passes nearest the
    # centre, at a distance q = cross(C - O, D), and h = sqrt(r^2 - q^2). A disc is met at
    # the near root, a ring (seen from inside) at the far one; at the hit point the cosine
    # between the ray and the normal is h / r.
    m = len(circles)
    radius = circles[:, 2]
    centres = circles[:, :2].T  # (2, m) metres
    b = rays.direction @ centres - rays.along[:, None]  # (16 * rays, m) metres
    q = rays.direction_perp @ centres - rays.across[:, None]  # (16 * rays, m) metres
    root = np.sqrt(radius * radius - q * q)  # (16 * rays, m) metres; nan where rays miss
    t = b - root if solid else b + root  # (16 * rays, m) metres
    flat, hit = _first(t, t > -behind_m)
    k = flat % m  # (16 * rays,) the circle each ray meets first
    if ideal:
        return hit, hit, k
    if solid:
        # A round pillar always turns part of its surface square to the transducer: when
        # any ray of the cone meets it, the echo returns from that nearest point of it.
        nearest = np.hypot(b.take(flat), q.take(flat)) - radius.take(k)
        return hit, np.where(np.isfinite(hit), nearest, np.inf), k
    cos_incidence = root.take(flat) / radius.take(k)
    rough = roughness.take(k)
    heard = (cos_incidence >= cos_specular) | (hit <= 0.0)
    heard |= (rough > 0.0) & (hit <= max_range_m * np.sqrt(rough * cos_incidence))
    return hit, np.where(heard, hit, np.inf), k
