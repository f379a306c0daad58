"""The simulated robot's configuration: its body, trajectories and sonar ring, with JSON
round trips, and the ring's mirror image.

The configuration is stored as JSON inside each log and FAM file, so a file describes the
robot that made it. Units are in the field names.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace
from typing import TYPE_CHECKING, Any, TypeVar

if TYPE_CHECKING:
    import numpy as np

SONAR_COUNT = 16

IndexT = TypeVar("IndexT", int, "np.ndarray")


@dataclass(frozen=True, slots=True)
class Trajectory:
    """One predefined path: a straight line or an arc, with its maximum speed."""

    name: str
    curvature_per_m: float  # 1 / radius; positive turns left (CCW), 0 is straight
    v_max_mps: float

    @property
    def radius_m(self) -> float:
        return float("inf") if self.curvature_per_m == 0 else 1.0 / abs(self.curvature_per_m)


def seven_trajectories(
    radii_m: tuple[float, float, float], v_max_mps: tuple[float, float, float, float]
) -> tuple[Trajectory, ...]:
    """The seven trajectories, left to right as in the paper's Figure 8(b): arcs of the
    three radii (tightest first) each way around the straight T0; `v_max_mps` are the top
    speeds of the tightest arcs, the middle ones, the widest and T0. Index 3 is straight
    ahead and index j mirrors index 6 - j."""
    arcs = [(f"T{3 - i}", radius, v_max_mps[i]) for i, radius in enumerate(radii_m)]
    left = [Trajectory(f"{name}L", 1.0 / radius, v) for name, radius, v in arcs]
    right = [Trajectory(f"{name}R", -1.0 / radius, v) for name, radius, v in reversed(arcs)]
    return (*left, Trajectory("T0", 0.0, v_max_mps[3]), *right)


DEFAULT_TRAJECTORIES = seven_trajectories(
    radii_m=(0.5, 1.0, 2.0), v_max_mps=(0.35, 0.45, 0.55, 0.60)
)
# The speeds a user may give lie within these: the robot drives no faster than its fastest
# trajectory (learning's speed), and a FAM's initial velocity is below its slowest's top.
FASTEST_MPS = max(t.v_max_mps for t in DEFAULT_TRAJECTORIES)
SLOWEST_TOP_MPS = min(t.v_max_mps for t in DEFAULT_TRAJECTORIES)


@dataclass(frozen=True, slots=True)
class SonarConfig:
    """The ring of transducers on the body edge, S0 forward, numbered counter-clockwise."""

    count: int = SONAR_COUNT
    min_range_m: float = 0.15
    max_range_m: float = 4.0
    cone_deg: float = 25.0
    rays_per_beam: int = 5
    specular_max_deg: float = 20.0  # beyond this incidence a smooth flat surface returns no echo
    # A convex edge (a block's corner, the end of a thin wall) diffracts a weak echo back to a
    # beam that meets its wall near it, heard only this close; 0 hears none.
    edge_echo_range_m: float = 0.0
    noise_sigma_m: float = 0.01
    noise_fraction: float = 0.01  # sigma grows by this fraction of the range
    ideal: bool = False  # nearest hit at any angle, no noise (ablations)


# Diffraction from an edge returns far less sound than a wall square on, heard out to about a
# quarter of the ring's maximum range (the `edges` sonar model).
EDGE_ECHO_FRACTION = 0.25
EDGE_ECHO_RANGE_M = EDGE_ECHO_FRACTION * SonarConfig().max_range_m  # the paper's robot's
# The sonar models a robot can learn and run with, by the name `--sonar` takes: each is its
# ring as built, heard another way.
SONAR_MODEL_NAMES = ("real", "edges", "ideal")


def sonar_model(ring: SonarConfig, name: str) -> SonarConfig:
    """A robot's ring as the named model hears: `real` (specular, noisy), `edges` (convex
    edges diffract back, within a quarter of its range) or `ideal` (the nearest hit at any
    angle, no noise)."""
    real = replace(ring, edge_echo_range_m=0.0, ideal=False)
    if name == "edges":
        return replace(real, edge_echo_range_m=EDGE_ECHO_FRACTION * ring.max_range_m)
    return replace(real, ideal=True) if name == "ideal" else real


# The paper's robot's ring in each model.
SONAR_MODELS: dict[str, SonarConfig] = {
    name: sonar_model(SonarConfig(), name) for name in SONAR_MODEL_NAMES
}


def sonar_model_name(sonar: SonarConfig) -> str | None:
    """The model a ring is heard by, or None for one heard otherwise (an edge range of its
    own, say)."""
    return next((name for name in SONAR_MODEL_NAMES if sonar_model(sonar, name) == sonar), None)


@dataclass(frozen=True, slots=True)
class RobotConfig:
    """The simulated robot: body, control timing, commands and sensors."""

    radius_m: float = 0.20
    control_period_s: float = 0.1
    physics_substeps: int = 4
    spin_rate_radps: float = 1.0
    odometry_noise_fraction: float = 0.01  # sigma of wheel travel, as a fraction of it
    trajectories: tuple[Trajectory, ...] = DEFAULT_TRAJECTORIES
    sonar: SonarConfig = field(default_factory=SonarConfig)

    def trajectory_index(self, name: str) -> int:
        """Index of a trajectory by name; ValueError naming the choices if unknown."""
        names = [t.name for t in self.trajectories]
        if name not in names:
            raise ValueError(f"unknown trajectory {name!r} (choose from {', '.join(names)})")
        return names.index(name)

    @property
    def v_max_mps(self) -> tuple[float, ...]:
        return tuple(t.v_max_mps for t in self.trajectories)

    @property
    def radii_m(self) -> tuple[float, ...]:
        """Each trajectory's turning radius (inf: straight)."""
        return tuple(t.radius_m for t in self.trajectories)

    def heard_by(self, model: str) -> RobotConfig:
        """This robot, its ring heard by the named sonar model (SONAR_MODEL_NAMES)."""
        return replace(self, sonar=sonar_model(self.sonar, model))

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> RobotConfig:
        """Build from a file's JSON; ValueError (or KeyError, TypeError) if it does not
        describe a robot that could move and sense."""
        fields = dict(data)
        fields["trajectories"] = tuple(Trajectory(**t) for t in data["trajectories"])
        fields["sonar"] = SonarConfig(**data["sonar"])
        robot = cls(**fields)
        _check_physical(robot)
        return robot


def _check_physical(robot: RobotConfig) -> None:
    """Sizes, times and speeds a robot can have: finite, positive where nothing else works."""
    sonar = robot.sonar
    positive = {
        "radius_m": robot.radius_m,
        "control_period_s": robot.control_period_s,
        "physics_substeps": robot.physics_substeps,
        "spin_rate_radps": robot.spin_rate_radps,
        "sonar.count": sonar.count,
        "sonar.min_range_m": sonar.min_range_m,
        "sonar.cone_deg": sonar.cone_deg,
        "sonar.rays_per_beam": sonar.rays_per_beam,
        **{f"{t.name}.v_max_mps": t.v_max_mps for t in robot.trajectories},
    }
    for name, value in positive.items():
        if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
            raise ValueError(f"robot {name} is {value!r}, not a positive number")
    others = {
        "odometry_noise_fraction": robot.odometry_noise_fraction,
        "sonar.noise_sigma_m": sonar.noise_sigma_m,
        "sonar.noise_fraction": sonar.noise_fraction,
        "sonar.specular_max_deg": sonar.specular_max_deg,
        **{f"{t.name}.curvature_per_m": t.curvature_per_m for t in robot.trajectories},
    }
    for name, value in others.items():
        if not (isinstance(value, int | float) and math.isfinite(value)):
            raise ValueError(f"robot {name} is {value!r}, not a number")
    if not sonar.max_range_m > sonar.min_range_m or not math.isfinite(sonar.max_range_m):
        raise ValueError(f"robot sonar ranges {sonar.min_range_m!r} to {sonar.max_range_m!r}")
    edge = sonar.edge_echo_range_m
    if not (isinstance(edge, int | float) and math.isfinite(edge) and edge >= 0):
        raise ValueError(f"robot sonar.edge_echo_range_m is {edge!r}, not a range >= 0")


ALL_TRAJECTORY_NAMES = tuple(t.name for t in DEFAULT_TRAJECTORIES)


def mirror_sonar(index: int, count: int = SONAR_COUNT) -> int:
    """The sonar in the mirror image of the ring across the forward axis: Si <-> S(16-i)."""
    return (-index) % count


def mirror_trajectory(index: IndexT, count: int) -> IndexT:
    """The trajectory turning as far the other way, of `count` listed left to right:
    j <-> count - 1 - j (the straight one mirrors itself). Indices may be an array."""
    return count - 1 - index


def sonars_within(angle_rad: float, count: int = SONAR_COUNT) -> tuple[int, ...]:
    """The sonars facing at most angle_rad to either side of straight ahead (S0 ahead, CCW)."""
    lowest = math.cos(angle_rad) - 1e-9  # the sideways sonars count at exactly 90 degrees
    return tuple(i for i in range(count) if math.cos(2 * math.pi * i / count) >= lowest)
