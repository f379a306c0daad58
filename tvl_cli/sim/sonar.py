"""The sonar ring: every beam's rays cast at once against all the static geometry in numpy.

Each transducer sits on the body edge and sends a cone sampled by a few rays. A ray's fate is
decided by the first surface it meets (the rest of the ray is reflected away, never seen):
- a flat wall or a ring wall echoes only when the ray meets it within the specular angle
  of its normal at the hit point (a wall seen at a grazing angle is invisible);
- a round pillar met by any ray of a cone echoes from its point nearest the transducer,
  whose normal faces the transducer;
- a concave corner (two walls meeting with the corner open towards the transducer) echoes
  from anywhere in the beam, as a corner reflector does, at the range of the corner itself;
- a convex edge (a block's corner, a thin wall's end) diffracts a weak echo back to a ray
  meeting its wall near it, heard within the ring's `edge_echo_range_m` (none by default);
- a rough wall (the world's `roughness` R) scatters part of the sound back whatever the
  incidence: Lambert's law gives a backscatter of R cos(incidence) of a square-on echo, and
  the two-way spreading loss of a point echo (1/r^2) then puts it above the threshold that a
  square-on echo meets at the maximum range only within max_range * sqrt(R cos(incidence)).
A transducer reads its nearest echo; no echo reads the maximum range.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tvl_cli.core.config import SonarConfig
from tvl_cli.sim.world import StaticGeometry

# A ray finds a corner when it hits one of the corner's walls within this many "footprints" of
# it, where a footprint is half the gap between neighbouring rays at that range. A corner lying
# between two rays is within one footprint of the nearer ray's line; on a wall met obliquely the
# hit point slides further along the wall (by 1/cos of the incidence, 1.41 at 45 degrees, the
# usual view into a square corner), so 1.5 footprints finds any corner inside the cone without
# widening the beam by more than half a ray spacing.
CORNER_FOOTPRINTS = 1.5
# Close in, the footprint shrinks to nothing while real corners are rounded and the transducer
# has a width; within this distance of a corner its echo always wins.
CORNER_MIN_RADIUS_M = 0.02


class SonarRing:
    """The ring of transducers on a body of the given radius; `read` returns their ranges."""

    def __init__(self, config: SonarConfig, body_radius_m: float) -> None:
        self.config = config
        self.body_radius_m = body_radius_m
        half_cone = math.radians(config.cone_deg) / 2.0
        rays = config.rays_per_beam
        offsets = np.linspace(-half_cone, half_cone, rays) if rays > 1 else np.zeros(1)
        sensor = 2.0 * math.pi * np.arange(config.count) / config.count  # (16,) rad, S0 ahead, CCW
        ray = (sensor[:, None] + offsets[None, :]).reshape(-1)  # (16 * rays,) rad from heading
        self._rays = len(ray)
        self._ray_index = np.arange(self._rays)  # (16 * rays,) beam by beam
        self._beam_of_ray = self._ray_index // rays  # (16 * rays,) transducer of each ray
        # Body-frame row vectors, stacked so that one small matrix product turns them all to a
        # pose: the transducers' outward normals U (16), the rays' directions D (16 * rays) and
        # the perpendiculars (dy, -dx) of those directions (16 * rays).
        self._body_vectors = np.concatenate(
            [
                np.stack([np.cos(sensor), np.sin(sensor)], axis=1),
                np.stack([np.cos(ray), np.sin(ray)], axis=1),
                np.stack([np.sin(ray), -np.cos(ray)], axis=1),
            ]
        )  # (16 + 2 * 16 * rays, 2)
        # A ray leaves its transducer at offset d from the transducer's normal U, so from the
        # transducer at P + rU: D.O = D.P + r cos(d) and cross(O, D) = cross(P, D) + r sin(d).
        ray_offset = np.tile(offsets, config.count)  # (16 * rays,) rad
        self._origin_terms = body_radius_m * np.concatenate(
            [np.cos(ray_offset), np.sin(ray_offset)]
        )  # (2 * 16 * rays,) metres
        self._corner_ends = np.array([0.0, 1.0])  # (2,) a wall's start and end, as fractions
        self._cos_specular = math.cos(math.radians(config.specular_max_deg))
        ray_gap = 2.0 * half_cone / (rays - 1) if rays > 1 else 2.0 * half_cone
        self._corner_slope = CORNER_FOOTPRINTS * math.tan(ray_gap / 2.0)
        # A wall farther than this from the centre can give no echo within range, nor hide
        # one: a corner echo is at most the corner slope (or its minimum radius) nearer than
        # the wall it is judged on.
        self._wall_reach_m = (
            body_radius_m + (config.max_range_m + CORNER_MIN_RADIUS_M) / (1.0 - self._corner_slope)
            if self._corner_slope < 1.0
            else math.inf
        )
        # A surface this close behind a transducer, along any of its rays, lies inside the body:
        # it can only be an obstacle the body overlaps during a contact, and reads as touching.
        self._behind_m = body_radius_m * math.cos(half_cone)

    def read(
        self,
        geometry: StaticGeometry,
        pose: tuple[float, float, float],
        rng: np.random.Generator,
    ) -> np.ndarray:
        """(16,) float64 metres from each transducer, S0 forward, counter-clockwise.

        Noise is drawn from rng (16 normal draws a reading) unless the ring is ideal.
        """
        cfg = self.config
        echo, _ = self._echoes(geometry, pose)
        nearest = echo.reshape(cfg.count, -1).min(axis=1)  # (16,) metres; inf: no echo
        heard = nearest <= cfg.max_range_m
        if not cfg.ideal:
            sigma = cfg.noise_sigma_m + cfg.noise_fraction * np.where(heard, nearest, 0.0)
            nearest = nearest + sigma * rng.standard_normal(cfg.count)
        measured = np.minimum(np.maximum(nearest, cfg.min_range_m), cfg.max_range_m)
        return np.where(heard, measured, cfg.max_range_m)

    def echo_sources(
        self, geometry: StaticGeometry, pose: tuple[float, float, float]
    ) -> tuple[np.ndarray, np.ndarray]:
        """Ground truth for a reading at `pose`, without noise: each transducer's nearest echo
        (16,) metres (inf: none within range) and the obstacle it came from (16,), as
        `StaticGeometry.element_of` numbers them (-1: none)."""
        echo, source = self._echoes(geometry, pose)
        per_beam = echo.reshape(self.config.count, -1)  # (16, rays) metres
        ray = per_beam.argmin(axis=1)  # (16,) the ray of each beam's nearest echo
        nearest = per_beam[np.arange(self.config.count), ray]
        heard = nearest <= self.config.max_range_m
        element = source.reshape(self.config.count, -1)[np.arange(self.config.count), ray]
        return np.where(heard, nearest, np.inf), np.where(heard, element, -1)

    def _echoes(
        self, geometry: StaticGeometry, pose: tuple[float, float, float]
    ) -> tuple[np.ndarray, np.ndarray]:
        """Every ray's echo (16 * rays,) metres (inf: none) and the obstacle it came from,
        numbered as `StaticGeometry.element_of` numbers them (-1 for a ray that meets none)."""
        rays = self._world_rays(pose)
        # A pillar's echo comes from its nearest point, up to a diameter nearer than where a
        # ray meets it: a wall in front of that meeting point still decides the echo.
        pillar_m = 2.0 * geometry.max_disc_radius_m
        near = geometry.segments_near(pose[0], pose[1], self._wall_reach_m + pillar_m)
        with np.errstate(divide="ignore", invalid="ignore"):
            found = []  # (hit, echo, source) triples, each (16 * rays,)
            if len(near.seg_len):
                hit, echo, k = self._segments(near, rays)
                found.append((hit, echo, near.segment_ids.take(k)))
            if len(near.discs):
                hit, echo, k = self._circles(near.discs, rays, 0.0, solid=True)
                found.append((hit, echo, geometry.element_of("disc", k)))
            if len(near.rings):
                hit, echo, k = self._circles(near.rings, rays, near.roughness, solid=False)
                found.append((hit, echo, geometry.element_of("ring", k)))
        if not found:
            return np.full(self._rays, np.inf), np.full(self._rays, -1)
        hit, echo, source = found[0]
        for other_hit, other_echo, other_source in found[1:]:
            # Where a ray meets this kind of surface first, its echo is this surface's.
            first = other_hit < hit
            echo = np.where(first, other_echo, echo)
            source = np.where(first, other_source, source)
            hit = np.minimum(hit, other_hit)
        return echo, np.where(np.isfinite(hit), source, -1)

    def rays(self, pose: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
        """Every ray's origin (16 * rays, 2) metres and unit direction (16 * rays, 2), beam by
        beam: for drawing beams, or casting them some other way."""
        rays = self._world_rays(pose)
        return rays.origin_of_ray[:, 0, :], rays.direction

    def _world_rays(self, pose: tuple[float, float, float]) -> _Rays:
        x, y, theta = pose
        cos_t, sin_t = math.cos(theta), math.sin(theta)
        turn = np.array([[cos_t, sin_t], [-sin_t, cos_t]])  # row vector @ turn: body -> world
        centre = np.array([x, y])  # (2,) metres
        vectors = self._body_vectors @ turn
        count, rays = self.config.count, self._rays
        direction_both = vectors[count:]  # (2 * 16 * rays, 2) D, then (dy, -dx)
        origin_terms = direction_both @ centre + self._origin_terms  # D.O, then cross(O, D)
        origin = centre + self.body_radius_m * vectors[:count]  # (16, 2) metres
        return _Rays(
            origin=origin,
            origin_of_ray=origin.take(self._beam_of_ray, axis=0)[:, None, :],
            direction=direction_both[:rays],
            direction_perp=direction_both[rays:],
            along=origin_terms[:rays],
            across=origin_terms[rays:],
        )

    def _first(self, t: np.ndarray, valid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per ray, the flat index of its nearest valid crossing in t (16 * rays, n), and its t."""
        np.putmask(t, ~valid, np.inf)
        n = t.shape[1]
        flat = self._ray_index * n + t.argmin(axis=1)  # (16 * rays,)
        return flat, t.take(flat)

    def _segments(
        self, g: StaticGeometry, rays: _Rays
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(hit, echo) metres for every ray against its nearest wall segment, and the
        segment's index in g."""
        # Ray O + tD meets segment A + sE where t = cross(A-O, E) / cross(D, E) and
        # s = cross(A-O, D) / cross(D, E); |cross(D, E)| / |E| is the cosine of incidence.
        # Each cross product splits into a matrix product and a per-ray or per-wall term.
        count, n = self.config.count, len(g.seg_len)
        denom = rays.direction @ g.seg_normal  # (16 * rays, n) cross(D, E)
        t_num = g.seg_moment - rays.origin @ g.seg_normal  # (16, n) cross(A - O, E)
        s_num = rays.direction_perp @ g.seg_start - rays.across[:, None]  # cross(A - O, D)
        t = (t_num[:, None, :] / denom.reshape(count, -1, n)).reshape(self._rays, n)  # metres
        s = s_num / denom  # (16 * rays, n) fraction along each segment
        flat, hit = self._first(t, (t > -self._behind_m) & (s >= 0.0) & (s <= 1.0))
        k = flat % n  # (16 * rays,) the wall each ray meets first
        if self.config.ideal:
            return hit, hit, k
        cross = denom.take(flat)
        length = g.seg_len.take(k)
        cos_incidence = np.abs(cross) / length
        specular = (cos_incidence >= self._cos_specular) | (hit <= 0.0)
        # For a forward hit the transducer is on the side of the wall given by the sign of
        # cross(D, E); a corner is concave when the other wall leaves it on that same side,
        # and an edge when it leaves on the other side or no wall meets it there.
        gap = np.abs(s.take(flat)[:, None] - self._corner_ends) * length[:, None]  # (., 2)
        reach = np.maximum(CORNER_MIN_RADIUS_M, self._corner_slope * hit)  # metres
        # A ray that meets no wall has no wall to judge a corner on: argmin named wall 0
        # for it, and an infinite reach would make that wall's corners echo.
        near_end = (gap <= reach[:, None]) & np.isfinite(hit)[:, None]  # (16 * rays, 2)
        side = g.corner_sides.take(k, axis=0) * cross[:, None]  # (16 * rays, 2)
        to_corner = g.seg_ends.take(k, axis=0) - rays.origin_of_ray  # (16 * rays, 2, 2) metres
        corner_m = np.hypot(to_corner[..., 0], to_corner[..., 1])  # (16 * rays, 2) metres
        heard = (side > 0.0) | (corner_m <= self.config.edge_echo_range_m)
        corner = np.where(near_end & heard, corner_m, np.inf).min(axis=1)
        if g.roughness > 0.0:
            diffuse_m = self.config.max_range_m * np.sqrt(g.roughness * cos_incidence)
            corner = np.minimum(corner, np.where(hit <= diffuse_m, hit, np.inf))
        return hit, np.where(specular, hit, corner), k

    def _circles(
        self, circles: np.ndarray, rays: _Rays, roughness: float, solid: bool
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(hit, echo) metres for every ray against its nearest disc (solid) or ring wall of
        the given roughness (a disc always echoes), and the circle's index."""
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
        flat, hit = self._first(t, t > -self._behind_m)
        k = flat % m  # (16 * rays,) the circle each ray meets first
        if self.config.ideal:
            return hit, hit, k
        if solid:
            # A round pillar always turns part of its surface square to the transducer: when
            # any ray of the cone meets it, the echo returns from that nearest point of it.
            nearest = np.hypot(b.take(flat), q.take(flat)) - radius.take(k)
            return hit, np.where(np.isfinite(hit), nearest, np.inf), k
        cos_incidence = root.take(flat) / radius.take(k)
        heard = (cos_incidence >= self._cos_specular) | (hit <= 0.0)
        if roughness > 0.0:
            heard |= hit <= self.config.max_range_m * np.sqrt(roughness * cos_incidence)
        return hit, np.where(heard, hit, np.inf), k


@dataclass(frozen=True, slots=True, eq=False)
class _Rays:
    """One reading's rays in the world frame, as row vectors."""

    origin: np.ndarray  # (16, 2) transducer positions, metres
    origin_of_ray: np.ndarray  # (16 * rays, 1, 2) each ray's transducer position, metres
    direction: np.ndarray  # (16 * rays, 2) unit vectors, beam by beam
    direction_perp: np.ndarray  # (16 * rays, 2) (dy, -dx)
    along: np.ndarray  # (16 * rays,) D.O, metres
    across: np.ndarray  # (16 * rays,) cross(O, D), metres
