"""Robot files (`--robot FILE.toml`): a robot of one's own, as changes to a shipped profile;
and the one resolver of a robot as a user names it, a profile's name or such a file.

# A robot a little wider than a TurtleBot3, with longer arcs.
base = "turtlebot3"            # the profile it changes (the paper's robot if not given)
radius_m = 0.14                # the body disc

[trajectories]
radii_m = [0.3, 0.6, 1.2]      # the arcs, tightest first, each way round
v_max_mps = [0.15, 0.18, 0.2, 0.22]  # the top speeds of those arcs, then of the straight

[sonar]                        # the ring of 16 transducers on the body's edge
min_range_m = 0.1
max_range_m = 3.5
cone_deg = 25.0

Every key is checked where it is read: one line naming the file and the key at the first
fault. The sonar model (`--sonar`) is the method's choice, not the robot's.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

from tvl_cli.core.errors import BadInput, check_in_range, did_you_mean
from tvl_cli.core.robot_config import RobotConfig, SonarConfig, Trajectory, seven_trajectories
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT_NAME, ROBOT_PROFILES
from tvl_cli.io.tomlfile import read_toml

# The ranges a robot's settings may take: a body from a toy's to a wheelchair's, arcs from
# spinning nearly in place to nearly straight, speeds a mobile robot drives indoors.
_RADIUS_M = (0.03, 1.0)
_ARC_RADIUS_M = (0.05, 50.0)
_SPEED_MPS = (0.01, 3.0)
_SPIN_RADPS = (0.05, 10.0)
_SONAR_RANGE_M = (0.01, 20.0)
_CONE_DEG = (1.0, 90.0)
_NOISE_M = (0.0, 1.0)
_FRACTION = (0.0, 0.5)
_INCIDENCE_DEG = (0.0, 90.0)

# Each number a file may set: its bounds and unit.
Bounds = dict[str, tuple[tuple[float, float], str]]
_BODY: Bounds = {
    "radius_m": (_RADIUS_M, "m"),
    "spin_rate_radps": (_SPIN_RADPS, "rad/s"),
    "odometry_noise_fraction": (_FRACTION, ""),
}
_TOP = ("base", *_BODY, "trajectories", "sonar")
_TRAJECTORIES = ("radii_m", "v_max_mps")
_SONAR: Bounds = {
    "min_range_m": (_SONAR_RANGE_M, "m"),
    "max_range_m": (_SONAR_RANGE_M, "m"),
    "cone_deg": (_CONE_DEG, "°"),
    "specular_max_deg": (_INCIDENCE_DEG, "°"),
    "noise_sigma_m": (_NOISE_M, "m"),
    "noise_fraction": (_FRACTION, ""),
}


def resolve_robot(named: RobotConfig | str | Path, label: str = "--robot") -> RobotConfig:
    """The robot a user names: a RobotConfig as given, a profile by name, else the robot
    file at that path. BadInput, led by `label`, for a name that is neither."""
    if isinstance(named, RobotConfig):
        return named
    if isinstance(named, str) and named in ROBOT_PROFILES:
        return ROBOT_PROFILES[named]
    path = Path(named)
    if not path.is_file():
        lead = f"{label} {named}" if label else str(named)
        raise BadInput(
            f"{lead}: neither a robot ({', '.join(ROBOT_PROFILES)}) nor a robot file "
            f"({did_you_mean(str(named), list(ROBOT_PROFILES))})"
        )
    return read_robot(path)


def read_robot(path: Path) -> RobotConfig:
    """The robot of a TOML file; BadInput naming the file and the key at the first fault."""
    return robot_from_table(read_toml(path, "robot"), str(path))


def robot_from_table(table: dict[str, Any], where: str) -> RobotConfig:
    """A robot file's table as the robot it describes."""
    _check_keys(table, _TOP, where, "")
    base_name = table.get("base", DEFAULT_ROBOT_NAME)
    if not isinstance(base_name, str) or base_name not in ROBOT_PROFILES:
        raise BadInput(f"{where}: base {base_name!r}: choose {', '.join(ROBOT_PROFILES)}")
    base = ROBOT_PROFILES[base_name]
    robot = replace(base, **_numbers_given(table, _BODY, where, ""))
    if "trajectories" in table:
        robot = replace(robot, trajectories=_trajectories(table["trajectories"], base, where))
    if "sonar" in table:
        robot = replace(robot, sonar=_sonar(table["sonar"], base.sonar, where))
    return robot


def _trajectories(table: object, base: RobotConfig, where: str) -> tuple[Trajectory, ...]:
    section = _table(table, "trajectories", where)
    _check_keys(section, _TRAJECTORIES, where, "trajectories.")
    left = base.trajectories[:4]  # the left arcs, tightest first, then the straight
    radii = section.get("radii_m", [t.radius_m for t in left[:3]])
    speeds = section.get("v_max_mps", [t.v_max_mps for t in left])
    r = _list(radii, 3, "trajectories.radii_m", _ARC_RADIUS_M, "m", where)
    v = _list(speeds, 4, "trajectories.v_max_mps", _SPEED_MPS, "m/s", where)
    if not r[0] < r[1] < r[2]:
        raise BadInput(f"{where}: trajectories.radii_m {r}: list the arcs tightest first")
    return seven_trajectories((r[0], r[1], r[2]), (v[0], v[1], v[2], v[3]))


def _sonar(table: object, base: SonarConfig, where: str) -> SonarConfig:
    section = _table(table, "sonar", where)
    _check_keys(section, tuple(_SONAR), where, "sonar.")
    sonar = replace(base, **_numbers_given(section, _SONAR, where, "sonar."))
    if not sonar.min_range_m < sonar.max_range_m:
        raise BadInput(
            f"{where}: sonar.min_range_m {sonar.min_range_m:g} must be below "
            f"sonar.max_range_m {sonar.max_range_m:g}"
        )
    return sonar


def _table(value: object, key: str, where: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise BadInput(f"{where}: {key} must be a table ([{key}])")
    return value


def _check_keys(table: dict[str, Any], known: tuple[str, ...], where: str, prefix: str) -> None:
    for key in table:
        if key not in known:
            raise BadInput(f"{where}: unknown key {prefix}{key} ({did_you_mean(key, known)})")


def _numbers_given(
    table: dict[str, Any], bounds: Bounds, where: str, prefix: str
) -> dict[str, Any]:
    """The numbers of `bounds` the table sets, each checked."""
    given = {key: table[key] for key in bounds if key in table}
    for key, value in given.items():
        (low, high), unit = bounds[key]
        check_in_range(value, f"{where}: {prefix}{key}", low, high, unit)
    return {key: float(value) for key, value in given.items()}


def _list(
    values: object, count: int, key: str, bounds: tuple[float, float], unit: str, where: str
) -> list[float]:
    if not isinstance(values, list) or len(values) != count:
        raise BadInput(f"{where}: {key} must be a list of {count} numbers")
    for value in values:
        check_in_range(value, f"{where}: {key}", *bounds, unit)
    return [float(v) for v in values]
