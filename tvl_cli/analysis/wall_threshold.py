"""Wall following against the velocity threshold (Figure 21): the wall runs' means at each
threshold, which settings are collision prone, and the ends the paper reports."""

from __future__ import annotations

from tvl_cli.analysis.aggregation import distinct, seed_interval, select
from tvl_cli.analysis.intervals import Interval
from tvl_cli.analysis.result_rows import Row
from tvl_cli.core import competence
from tvl_cli.core.behaviours import BEHAVIOUR_NAMES

# A setting is collision prone above the competence limit (dashed in Figure 21).
COLLISION_PRONE_PER_MIN = competence.MAX_CONTACTS_PER_MIN
WALL_BEHAVIOURS = tuple(name for name in BEHAVIOUR_NAMES if name.startswith("wall"))
# The paper's reported ends (SPEC §10) in wall following (§5.1, Fig. 21): threshold ->
# (wall clearance m, mean speed m/s).
PAPER_FIG21 = {0.65: (0.32, 0.32), 0.95: (0.67, 0.45)}


def threshold_points(rows: list[Row], world: str) -> list[tuple[float, dict[str, Interval | None]]]:
    """Per threshold, the means over trials (each trial's wall sides averaged) of one world's
    wall runs, with their 95 % intervals."""
    walls = select(rows, kind="tvl", world=world, behaviour=WALL_BEHAVIOURS)
    return [
        (
            threshold,
            {
                key: seed_interval(select(walls, threshold=threshold), key)
                for key in ("mean_wall_clearance_m", "mean_speed_mps", "contacts_per_min")
            },
        )
        for threshold in distinct(walls, "threshold")
    ]


def prone(point: dict[str, Interval | None]) -> bool:
    rate = point["contacts_per_min"]
    return rate is not None and rate.mean > COLLISION_PRONE_PER_MIN
