"""Text map -> WorldMap: pure parsing with errors that name file, line and column."""

from __future__ import annotations

from dataclasses import dataclass

Segment = tuple[float, float, float, float]  # x1, y1, x2, y2 in metres
Circle = tuple[float, float, float]  # x, y, radius in metres


@dataclass(frozen=True, slots=True)
class WorldMap:
    """A world: static geometry in metres, origin bottom-left, x right, y up."""

    name: str
    cell_m: float
    width_m: float
    height_m: float
    segments: tuple[Segment, ...]  # maximal straight wall outlines
    discs: tuple[Circle, ...]  # round pillars (solid)
    rings: tuple[Circle, ...]  # circular walls; the robot lives inside
    start: tuple[float, float, float]  # x, y, heading (radians, CCW from +x)
    goals: tuple[tuple[float, float], ...]
    text: str  # the source, stored in every log so a world travels with its data
