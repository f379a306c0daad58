"""How long and how fast the robot explores, and how far it backs off after a bump: plain
values, stored with each log session beside its method, that the learning loop, the sweep's
cells and the benchmark's suites all read."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from tvl_cli.core.errors import BadInput, check_minutes
from tvl_cli.core.robot_config import FASTEST_MPS

# Reversed along the path after a collision while learning (paper Fig. 14), and by the
# back-off reflexes while behaving.
BACKOFF_M = 0.15


@dataclass(frozen=True, slots=True)
class LearnParams:
    """How long and how fast the robot explores; stored with each log session beside its
    method. (Where collision points fall and which pair comes next are the method's.)"""

    minutes: float = 15.0
    learn_speed_mps: float = 0.2
    straight_run_m: float = 8.0  # a T0 run this long without a bump counts as free
    reverse_m: float = BACKOFF_M  # backed off along the path after a collision

    def __post_init__(self) -> None:
        check_minutes(self.minutes)
        if not (math.isfinite(self.learn_speed_mps) and 0 < self.learn_speed_mps <= FASTEST_MPS):
            raise BadInput(
                f"--learn-speed {self.learn_speed_mps:g} must be > 0 and at most "
                f"{FASTEST_MPS:g} m/s, the fastest trajectory's"
            )

    def to_dict(self) -> dict[str, float | str]:
        return asdict(self)
