"""The sonar ring: every beam's rays cast against the static geometry near the robot.

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
- a rough wall (roughness R, the world's) scatters part of the sound back whatever the
  incidence: Lambert's law gives a backscatter of R cos(incidence) of a square-on echo, and
  the two-way spreading loss of a point echo (1/r^2) then puts it above the threshold that a
  square-on echo meets at the maximum range only within max_range * sqrt(R cos(incidence)).
A transducer reads its nearest echo; no echo reads the maximum range. The casting itself is
a compiled kernel, sim.ring_kernel.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from tvl_cli.core.robot_config import SonarConfig
from tvl_cli.sim.geometry import StaticGeometry

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
        # Imported on first use, with the compiler behind it, so that no `--help` loads it.
        from tvl_cli.sim.ring_kernel import ring_ranges

        self._ring_ranges: Callable[..., None] = ring_ranges
        self.config = config
        self.body_radius_m = body_radius_m
        half_cone = math.radians(config.cone_deg) / 2.0
        rays = config.rays_per_beam
        offsets = np.linspace(-half_cone, half_cone, rays) if rays > 1 else np.zeros(1)
        sensor = 2.0 * math.pi * np.arange(config.count) / config.count  # (16,) rad, S0 ahead, CCW
        ray = (sensor[:, None] + offsets[None, :]).reshape(-1)  # (16 * rays,) rad from heading
        ray_offset = np.tile(offsets, config.count)  # (16 * rays,) rad from its transducer
        # The body-frame layout the kernel turns to each pose: transducer normals (16, 2), and
        # each ray's direction and its offset as body_radius_m * (cos, sin) (16 * rays, 4).
        self._layout = (
            np.stack([np.cos(sensor), np.sin(sensor)], axis=1),
            np.stack(
                [
                    np.cos(ray),
                    np.sin(ray),
                    body_radius_m * np.cos(ray_offset),
                    body_radius_m * np.sin(ray_offset),
                ],
                axis=1,
            ),
        )
        ray_gap = 2.0 * half_cone / (rays - 1) if rays > 1 else 2.0 * half_cone
        corner_slope = CORNER_FOOTPRINTS * math.tan(ray_gap / 2.0)
        # A crossing farther than this along a ray from its transducer can give no echo
        # within range, nor hide one: a corner echo is at most the corner slope (or its
        # minimum radius) nearer than the wall it is judged on.
        self._wall_reach_m = (
            (config.max_range_m + CORNER_MIN_RADIUS_M) / (1.0 - corner_slope)
            if corner_slope < 1.0
            else math.inf
        )
        self._model = (
            body_radius_m,
            # A surface this close behind a transducer, along any of its rays, lies inside the
            # body: it can only be an obstacle the body overlaps during a contact, and reads as
            # touching.
            body_radius_m * math.cos(half_cone),
            math.cos(math.radians(config.specular_max_deg)),
            corner_slope,
            CORNER_MIN_RADIUS_M,
            config.edge_echo_range_m,
            config.max_range_m,
            config.min_range_m,
            config.noise_sigma_m,
            config.noise_fraction,
            config.ideal,
        )  # as sim.ring_kernel documents it
        self._quiet = np.zeros((1, config.count))  # (1, 16) the noise of a reading without any

    def read(
        self,
        geometry: StaticGeometry,
        pose: tuple[float, float, float],
        rng: np.random.Generator,
    ) -> np.ndarray:
        """(16,) float64 metres from each transducer, S0 forward, counter-clockwise.

        Noise is drawn from rng (16 normal draws a reading) unless the ring is ideal or the
        world holds nothing to hear.
        """
        noise = self._quiet
        if self._noisy(geometry):
            noise = rng.standard_normal(self.config.count)[None, :]
        return self._cast(geometry, pose, noise)[0]

    def read_many(
        self, geometry: StaticGeometry, poses: np.ndarray, rngs: Sequence[np.random.Generator]
    ) -> np.ndarray:
        """(N, 16) float64 metres read by N robots at poses (N, 3) (x, y metres, heading rad)
        in one kernel call, robot i's noise drawn from rngs[i] just as `read` draws it."""
        noise = np.zeros((len(poses), self.config.count))  # (N, 16) standard normal draws
        if self._noisy(geometry):
            for row, rng in zip(noise, rngs, strict=True):
                rng.standard_normal(out=row)
        return self.ranges(geometry, poses, noise)

    def _noisy(self, geometry: StaticGeometry) -> bool:
        """Whether a reading draws noise: not from an ideal ring, nor in a world with nothing
        in it to hear."""
        return not self.config.ideal and bool(
            len(geometry.seg_len) or len(geometry.discs) or len(geometry.rings)
        )

    def echo_sources(
        self, geometry: StaticGeometry, pose: tuple[float, float, float]
    ) -> tuple[np.ndarray, np.ndarray]:
        """Ground truth for a reading at `pose`, without noise: each transducer's range
        (16,) metres (the maximum where nothing echoes) and the obstacle it heard (16,), as
        StaticGeometry.element_of numbers them (-1: none)."""
        return self._cast(geometry, pose, self._quiet)

    def _cast(
        self, geometry: StaticGeometry, pose: tuple[float, float, float], noise: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """One robot's readings (16,) metres and the obstacles they heard (16,)."""
        readings = np.empty((1, self.config.count))  # (1, 16) metres
        sources = np.empty((1, self.config.count), dtype=np.int64)  # (1, 16) obstacles
        self._ring_ranges(*self.cast_inputs(geometry, np.array([pose]), noise), readings, sources)
        return readings[0], sources[0]

    def ranges(self, geometry: StaticGeometry, poses: np.ndarray, noise: np.ndarray) -> np.ndarray:
        """(N, 16) metres read by N robots at poses (N, 3) (x, y metres, heading rad), with
        standard normal draws noise (N, 16): one kernel call for them all."""
        readings = np.empty((len(poses), self.config.count))  # (N, 16) metres
        sources = np.empty((len(poses), self.config.count), dtype=np.int64)  # (N, 16)
        self._ring_ranges(*self.cast_inputs(geometry, poses, noise), readings, sources)
        return readings

    def cast_inputs(
        self, geometry: StaticGeometry, poses: np.ndarray, noise: np.ndarray
    ) -> tuple[object, ...]:
        """The arguments of sim.ring_kernel.ring_ranges for N robots at poses (N, 3), but
        the readings (N, 16) it fills."""
        g = geometry
        walls = (g.seg_start, g.seg_normal, g.seg_moment, g.seg_len, g.seg_ends, g.corner_sides,
                 g.seg_roughness)  # fmt: skip
        return (
            poses, noise, self._layout, walls, g.grid.kernel_input, self._reach_m(g), g.discs,
            g.rings, g.ring_roughness, self._model,
        )  # fmt: skip

    def _reach_m(self, geometry: StaticGeometry) -> float:
        """How far along a ray from its transducer a crossing may decide an echo."""
        # A pillar's echo comes from its nearest point, up to a diameter nearer than where a
        # ray meets it: a wall in front of that meeting point still decides the echo.
        return self._wall_reach_m + 2.0 * geometry.max_disc_radius_m

    def rays(self, pose: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
        """Every ray's origin (16 * rays, 2) metres and unit direction (16 * rays, 2), beam by
        beam: for drawing beams, or casting them some other way."""
        x, y, theta = pose
        transducers, rays = self._layout
        per_beam = len(rays) // len(transducers)
        normal = np.repeat(_turned(transducers, theta), per_beam, axis=0)  # (16 * rays, 2)
        return np.array([x, y]) + self.body_radius_m * normal, _turned(rays[:, :2], theta)


def _turned(vectors: np.ndarray, theta: float) -> np.ndarray:
    """Body-frame row vectors (k, 2) turned to a heading of theta radians."""
    cos_t, sin_t = math.cos(theta), math.sin(theta)
    return vectors @ np.array([[cos_t, sin_t], [-sin_t, cos_t]])
