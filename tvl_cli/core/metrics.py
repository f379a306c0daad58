"""Run metrics accumulated step by step: distance, speed, collisions, clearances, goal."""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class RunMetrics:
    """What `tvl run --json` prints; keys and units fixed by the command-line contract."""

    sim_s: float
    distance_m: float
    mean_speed_mps: float
    collisions: int
    collisions_per_min: float
    mean_clearance_m: float
    mean_wall_clearance_m: float | None  # None unless a wall was being followed
    goal_reached: bool
    time_to_goal_s: float | None
    trapped: int


class MetricsRecorder:
    """Fed once per control step (of a fixed period) with the true state after the step."""

    def __init__(self, start_xy: tuple[float, float]) -> None:
        self._last_xy = start_xy
        self._sim_s = 0.0
        self._distance_m = 0.0
        self._collisions = 0
        self._was_bumped = False
        self._clearance_sum = 0.0
        self._steps = 0
        self._wall_clearance_sum = 0.0
        self._wall_steps = 0
        self._trapped = 0
        self._time_to_goal_s: float | None = None

    def record(
        self,
        xy: tuple[float, float],
        dt_s: float,
        bumped: bool,
        clearance_m: float,
        following_wall: bool,
    ) -> None:
        self._steps += 1
        # Counted, not summed: 3000 additions of 0.1 s fall short of 300 s, and one collision
        # in five minutes would then be a hair over 0.2 a minute.
        self._sim_s = self._steps * dt_s
        self._distance_m += math.dist(xy, self._last_xy)
        self._last_xy = xy
        # A collision is an event: the step the bump sensor closes, not every step it stays closed.
        if bumped and not self._was_bumped:
            self._collisions += 1
        self._was_bumped = bumped
        self._clearance_sum += clearance_m
        if following_wall:
            self._wall_clearance_sum += clearance_m
            self._wall_steps += 1

    def trapped(self) -> None:
        self._trapped += 1

    def goal_reached(self) -> None:
        if self._time_to_goal_s is None:
            self._time_to_goal_s = self._sim_s

    def result(self) -> RunMetrics:
        minutes = self._sim_s / 60.0
        return RunMetrics(
            sim_s=self._sim_s,
            distance_m=self._distance_m,
            mean_speed_mps=self._distance_m / self._sim_s if self._sim_s else 0.0,
            collisions=self._collisions,
            collisions_per_min=self._collisions / minutes if minutes else 0.0,
            mean_clearance_m=self._clearance_sum / self._steps if self._steps else 0.0,
            mean_wall_clearance_m=(
                self._wall_clearance_sum / self._wall_steps if self._wall_steps else None
            ),
            goal_reached=self._time_to_goal_s is not None,
            time_to_goal_s=self._time_to_goal_s,
            trapped=self._trapped,
        )
