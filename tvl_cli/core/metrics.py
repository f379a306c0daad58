"""Run metrics accumulated step by step: distance, speed, contacts, clearances, goal."""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass

from tvl_cli.core.contacts import BACKOFF, BUMP, NEAR_MISS, SPIN, TRAPPED


@dataclass(frozen=True, slots=True)
class RunMetrics:
    """What `tvl run --json` prints; keys and units fixed by the command-line contract."""

    sim_s: float
    distance_m: float
    mean_speed_mps: float  # over the whole run, stops, spins and back-offs included
    mean_drive_speed_mps: float  # over the steps that drove forward
    collisions: int
    near_misses: int
    contacts: int  # collisions + near misses
    contacts_per_min: float
    collisions_per_min: float
    backoffs: int
    spins: int
    trapped: int
    mean_clearance_m: float
    mean_wall_clearance_m: float | None  # None unless a wall was being followed
    goal_reached: bool | None  # None for a run that sought no goal
    time_to_goal_s: float | None


class MetricsRecorder:
    """Fed once per control step (of a fixed period) with the true state after the step."""

    def __init__(self, start_xy: tuple[float, float], seeks_goal: bool = False) -> None:
        self._seeks_goal = seeks_goal
        self._last_xy = start_xy
        self._sim_s = 0.0
        self._distance_m = 0.0
        self._drive_distance_m = 0.0
        self._drive_steps = 0
        self._dt_s = 0.0
        self._events: Counter[str] = Counter()
        self._clearance_sum = 0.0
        self._steps = 0
        self._wall_clearance_sum = 0.0
        self._wall_steps = 0
        self._time_to_goal_s: float | None = None

    def record(
        self,
        xy: tuple[float, float],
        dt_s: float,
        clearance_m: float,
        following_wall: bool,
        driving_forward: bool,
        events: Iterable[str],
    ) -> None:
        self._steps += 1
        self._dt_s = dt_s
        # Counted, not summed: 3000 additions of 0.1 s fall short of 300 s, and one collision
        # in five minutes would then be a hair over 0.2 a minute.
        self._sim_s = self._steps * dt_s
        moved_m = math.dist(xy, self._last_xy)
        self._distance_m += moved_m
        if driving_forward:
            self._drive_distance_m += moved_m
            self._drive_steps += 1
        self._last_xy = xy
        self._events.update(events)
        self._clearance_sum += clearance_m
        if following_wall:
            self._wall_clearance_sum += clearance_m
            self._wall_steps += 1

    def count(self, events: Iterable[str]) -> None:
        """Events judged after the last step (an approach still open when the run ends)."""
        self._events.update(events)

    def goal_reached(self) -> None:
        if self._time_to_goal_s is None:
            self._time_to_goal_s = self._sim_s

    def result(self) -> RunMetrics:
        minutes = self._sim_s / 60.0
        collisions, near_misses = self._events[BUMP], self._events[NEAR_MISS]
        drive_s = self._drive_steps * self._dt_s
        return RunMetrics(
            sim_s=self._sim_s,
            distance_m=self._distance_m,
            mean_speed_mps=self._distance_m / self._sim_s if self._sim_s else 0.0,
            mean_drive_speed_mps=self._drive_distance_m / drive_s if drive_s else 0.0,
            collisions=collisions,
            near_misses=near_misses,
            contacts=collisions + near_misses,
            contacts_per_min=(collisions + near_misses) / minutes if minutes else 0.0,
            collisions_per_min=collisions / minutes if minutes else 0.0,
            backoffs=self._events[BACKOFF],
            spins=self._events[SPIN],
            trapped=self._events[TRAPPED],
            mean_clearance_m=self._clearance_sum / self._steps if self._steps else 0.0,
            mean_wall_clearance_m=(
                self._wall_clearance_sum / self._wall_steps if self._wall_steps else None
            ),
            goal_reached=self._time_to_goal_s is not None if self._seeks_goal else None,
            time_to_goal_s=self._time_to_goal_s,
        )


@dataclass(frozen=True, slots=True)
class MinuteContacts:
    """A run's contacts in one simulated minute (`tvl run --json`'s `minutes`)."""

    minute: int  # counted from 1, as every table and figure counts minutes
    sim_s: float  # simulated seconds of it the run lasted (a last minute may be partial)
    collisions: int
    near_misses: int
    contacts: int  # collisions + near misses


class MinuteTally:
    """Counts a run's contacts per simulated minute, fed each step's events in order."""

    def __init__(self, dt_s: float) -> None:
        self._dt_s = dt_s
        self._per_minute = round(60.0 / dt_s)  # steps, counted: sums of 0.1 s drift
        self._steps = 0
        self._collisions: list[int] = []
        self._near_misses: list[int] = []

    def record(self, events: Iterable[str]) -> None:
        if self._steps % self._per_minute == 0:
            self._collisions.append(0)
            self._near_misses.append(0)
        self._steps += 1
        for event in events:
            if event == BUMP:
                self._collisions[-1] += 1
            elif event == NEAR_MISS:
                self._near_misses[-1] += 1

    def minutes(self, run: RunMetrics) -> list[MinuteContacts]:
        """The minutes of `run`, whose totals also count an approach still open when it
        ended (MetricsRecorder.count): that near miss belongs to the last minute."""
        near_misses = list(self._near_misses)
        if near_misses:
            near_misses[-1] += run.near_misses - sum(near_misses)
        return [
            MinuteContacts(
                minute=k + 1,
                sim_s=min(self._per_minute, self._steps - k * self._per_minute) * self._dt_s,
                collisions=c,
                near_misses=n,
                contacts=c + n,
            )
            for k, (c, n) in enumerate(zip(self._collisions, near_misses, strict=True))
        ]
