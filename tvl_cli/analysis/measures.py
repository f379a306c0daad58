"""What a run measures, for people: each `tvl run --json` metric's label with its unit, and
how it is rounded, as a sweep's table and plot show it."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from tvl_cli.analysis.intervals import Bounds
from tvl_cli.analysis.wall_threshold import WALL_BEHAVIOURS


@dataclass(frozen=True, slots=True)
class Measure:
    label: str  # with its unit: a table's header, a plot's axis
    decimals: int  # shown rounded to these, after scaling
    scale: float = 1.0  # shown times this: a share of runs as a percentage
    # What it can be, which bounds its intervals: every measure of a run counts or measures
    # something, so is never below 0, and a share is at most 1.
    bounds: Bounds = (0.0, None)


SHARE: Bounds = (0.0, 1.0)


# Every RunMetrics field, in its order.
MEASURES: dict[str, Measure] = {
    "sim_s": Measure("simulated (s)", 0),
    "distance_m": Measure("distance (m)", 1),
    "mean_speed_mps": Measure("speed (m/s)", 3),
    "mean_drive_speed_mps": Measure("driving speed (m/s)", 3),
    "collisions": Measure("collisions", 1),
    "near_misses": Measure("near misses", 1),
    "contacts": Measure("contacts", 1),
    "contacts_per_min": Measure("contacts/min", 2),
    "collisions_per_min": Measure("collisions/min", 2),
    "backoffs": Measure("back-offs", 1),
    "spins": Measure("spins", 1),
    "trapped": Measure("trapped", 1),
    "mean_clearance_m": Measure("clearance (m)", 3),
    "mean_wall_clearance_m": Measure("wall clearance (m)", 3),
    "goal_reached": Measure("goal reached (%)", 0, scale=100.0, bounds=SHARE),
    "time_to_goal_s": Measure("time to goal (s)", 1),
}


def headline(behaviours: Iterable[str]) -> tuple[str, ...]:
    """The measures a table shows first for runs of these behaviours: contacts and speed,
    with the wall clearance of wall following and the goals reached of goal seeking."""
    kinds = set(behaviours)
    shown = ["contacts_per_min", "mean_speed_mps"]
    if kinds.intersection(WALL_BEHAVIOURS):
        shown.append("mean_wall_clearance_m")
    if "goal" in kinds:
        shown.append("goal_reached")
    return tuple(shown)


def measure_bounds(measures: Iterable[str]) -> dict[str, Bounds]:
    """The bounds of the measures' intervals, by name."""
    return {name: MEASURES[name].bounds for name in measures}
