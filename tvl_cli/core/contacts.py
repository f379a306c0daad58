"""Contacts, defined once: what every run counts, whatever policy or reflexes drive it.

A *collision* is the step the bump sensor closes. A *near miss* is an approach in which a
sonar within NEAR_MISS_WITHIN_RAD of straight ahead reads inside its blind zone (at its
minimum range) while the robot drives forward: the ring can no longer tell how close the
object is. An approach that ends in touching counts once, as a collision. A *contact* is
either. Back-offs, spins and trapped events are counted beside them.
"""

from __future__ import annotations

import math

import numpy as np

from tvl_cli.core.drive_command import Command
from tvl_cli.core.robot_config import sonars_within

# Sideways sonars do not count: a wall alongside, as in a narrow passage, is passed, not met.
NEAR_MISS_WITHIN_RAD = math.pi / 4

BUMP = "bump"
NEAR_MISS = "near-miss"
BACKOFF = "backoff"
BACKOFF_END = "backoff-end"
SPIN = "spin"
TRAPPED = "trapped"
# Every event a run trace records, in the order of their bits.
EVENTS = (BUMP, NEAR_MISS, BACKOFF, BACKOFF_END, SPIN, TRAPPED)
# `tvl explain --event collision` is the bump event under the name a person looks for.
EVENT_ALIASES = {"collision": BUMP}
EVENT_CHOICES = (*EVENT_ALIASES, *EVENTS)


def steps_beginning(events: np.ndarray, event: str) -> np.ndarray:
    """The indices of the steps that began `event`, from per-step event bits (bit i is
    EVENTS[i])."""
    return np.flatnonzero(np.asarray(events) & (1 << EVENTS.index(event)))


def near_miss_sonars(sonar_count: int) -> tuple[int, ...]:
    """The sonars whose blind zone counts for a near miss."""
    return sonars_within(NEAR_MISS_WITHIN_RAD, sonar_count)


def blind_ahead(ring_m: np.ndarray, sonars: tuple[int, ...], min_range_m: float) -> bool:
    """A sonar ahead reads its minimum range: something is inside its blind zone."""
    # Asked several times a control step, of five readings: a Python loop costs a third of
    # numpy's fancy indexing and reduction.
    return any(ring_m[i] <= min_range_m for i in sonars)


def drives_forward(command: Command | None) -> bool:
    return command is not None and command.linear_mps > 0.0


def is_spin(command: Command) -> bool:
    return command.linear_mps == 0.0 and command.angular_radps != 0.0


class EventDetector:
    """Turns each control step into the events it begins, from what the loop saw.

    Fed in step order: the ring read before the step (or None when no one read it, which
    happens only when the last command did not drive forward), the command, the bump
    sensor after the step, and whether the policy found itself trapped.
    """

    def __init__(self, sonars: tuple[int, ...], min_range_m: float) -> None:
        self._sonars = sonars
        self._min_range_m = min_range_m
        self._last: Command | None = None
        self._was_bumped = False
        self._approach = False  # inside a near-miss approach since an earlier step
        self._approach_bumped = False

    def needs_ring(self) -> bool:
        """Whether the next step's near-miss test needs the ring (the last command drove on)."""
        return drives_forward(self._last)

    def step(
        self, ring_m: np.ndarray | None, command: Command, bumped: bool, trapped: bool
    ) -> tuple[str, ...]:
        events: list[str] = []
        blind = (
            ring_m is not None
            and drives_forward(self._last)
            and blind_ahead(ring_m, self._sonars, self._min_range_m)
        )
        if blind and not self._approach:
            self._approach, self._approach_bumped = True, False
        elif not blind and self._approach:
            events += self._end_approach()
        if bumped and not self._was_bumped:
            events.append(BUMP)
            self._approach_bumped = True
        last = self._last
        if command.linear_mps < 0.0 and not (last is not None and last.linear_mps < 0.0):
            events.append(BACKOFF)
        if last is not None and last.linear_mps < 0.0 and command.linear_mps >= 0.0:
            events.append(BACKOFF_END)
        if is_spin(command) and not (last is not None and is_spin(last)):
            events.append(SPIN)
        if trapped:
            events.append(TRAPPED)
        self._last = command
        self._was_bumped = bumped
        return tuple(events)

    def _end_approach(self) -> list[str]:
        self._approach = False
        return [] if self._approach_bumped else [NEAR_MISS]

    def finish(self) -> tuple[str, ...]:
        """Events still open when the run ends: an approach that has not touched."""
        return tuple(self._end_approach()) if self._approach else ()
