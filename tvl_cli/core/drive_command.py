"""A wheel command for one control period: forward speed and turn rate (a unicycle)."""

from __future__ import annotations

from dataclasses import dataclass

from tvl_cli.core.robot_config import Trajectory


@dataclass(frozen=True, slots=True)
class Command:
    """Held for one control period. Negative speed on an arc reverses along that same arc."""

    linear_mps: float
    angular_radps: float

    @classmethod
    def follow(cls, trajectory: Trajectory, speed_mps: float) -> Command:
        return cls(speed_mps, speed_mps * trajectory.curvature_per_m)

    @classmethod
    def spin(cls, rate_radps: float) -> Command:
        return cls(0.0, rate_radps)


STOP = Command(0.0, 0.0)
