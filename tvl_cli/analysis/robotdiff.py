"""How the robots two FAMs were learnt on differ: a FAM's velocities are what its robot (body,
trajectories, sonar ring) could drive, so two learnt on different robots differ for that
alone, rule by rule, and the comparison must say so."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from tvl_cli.core.robot_config import RobotConfig, sonar_model_name

SONAR = "sonar"


@dataclass(frozen=True, slots=True)
class RobotDifference:
    """One setting of the robot that differs: its name as the robot's configuration names it
    (`radius_m`, `trajectories.T1L.v_max_mps`), or `sonar` for two named sonar models."""

    setting: str
    first: Any  # in the first FAM's robot; None where it has no such setting
    second: Any

    def to_dict(self) -> dict[str, Any]:
        return {"setting": self.setting, "first": self.first, "second": self.second}

    def text(self) -> str:
        return f"{self.setting} {_shown(self.first)} → {_shown(self.second)}"


def robot_differences(first: RobotConfig, second: RobotConfig) -> list[RobotDifference]:
    """Every setting on which the two robots differ, in the configuration's order; the sonar
    by its model's name where both rings are models tvl names (real, edges, ideal)."""
    a, b = _flat(first.to_dict()), _flat(second.to_dict())
    models = sonar_model_name(first.sonar), sonar_model_name(second.sonar)
    named = None not in models and models[0] != models[1]
    found = [RobotDifference(SONAR, *models)] if named else []
    for setting in dict.fromkeys([*a, *b]):
        if named and setting.startswith(f"{SONAR}."):
            continue
        if a.get(setting) != b.get(setting):
            found.append(RobotDifference(setting, a.get(setting), b.get(setting)))
    return found


def _flat(value: Any, prefix: str = "") -> dict[str, Any]:
    """Settings by dotted name; a list's items by their own `name` where they have one."""
    items: list[tuple[Any, Any]]
    if isinstance(value, dict):
        items = list(value.items())
    elif isinstance(value, list | tuple) and all(
        isinstance(v, dict) and "name" in v for v in value
    ):
        items = [(v["name"], {k: x for k, x in v.items() if k != "name"}) for v in value]
    else:
        return {prefix: value}
    flat: dict[str, Any] = {}
    for key, inner in items:
        flat.update(_flat(inner, f"{prefix}.{key}" if prefix else str(key)))
    return flat


def _shown(value: Any) -> str:
    if value is None:
        return "none"
    return f"{value:g}" if isinstance(value, float) else str(value)
