"""The echo memory's settings, and the geometry of what it remembers.

A specular ring hears a smooth wall only near square on, so a wall met at a slant is often
silent at the moment the FAM must rate the way ahead, though a side sonar heard it square on
a moment earlier. The echo memory keeps the echoes of the last few seconds in the odometry
frame and gives the FAM a *virtual ring*: each sonar reads the nearer of its live range and
the nearest remembered surface in its cone, as seen from where odometry says the robot is
now. It never uses the true pose or the map.

What an echo is remembered as (`kind`):
- `none`: nothing; the virtual ring is the live ring (the paper's perception).
- `points`: the point on the transducer's axis at the echo's range. A later beam reads it
  when the point lies inside its cone.
- `patches`: a piece of surface square to the beam, centred on that point, as wide as the
  beam was there (`patch_m` across at least). A specular echo returns only from a surface
  facing the transducer, and the part of it inside the cone is what was heard; a later beam
  meets it like a wall, at any angle, from the side it was heard from.

When a live echo clears remembered patches (`clearing`): a patch heard from afar is as wide
as the beam was there, and the surface that echoed may be far narrower (a pillar, a door's
edge). Such patches, side by side, close the gaps between pillars and the doorways a goal
lies through. Where clearing holds, a beam whose live reading heard an echo meets only the
patches no wider than CLEARED_ABOVE_M either side (heard from near, where the beam is
narrow); a wider one in it is left out for that beam, since the beam heard farther. A beam
that hears nothing still meets every patch: a slanted wall is silent, and that is what the
memory is for.
- `never`: every beam meets every patch (the memory as it was first built);
- `goal`: while seeking a goal, where the way must open;
- `toward-goal` (ours): as `goal`, and besides, the beam facing the goal (the one nearest its
  bearing, and GOAL_BEAMS_EITHER_SIDE either side) meets no patch at all where it hears an echo:
  the way to the goal is judged by what is heard along it now. Near patches close a gap
  as surely as far ones: one is placed on the beam's axis, where the surface that echoed
  may lie anywhere across the cone;
- `always`: in every behaviour, and while learning.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

from tvl_cli.core.errors import BadInput, check_in_range

NONE, POINTS, PATCHES = "none", "points", "patches"
MEMORY_KINDS = (NONE, POINTS, PATCHES)
NEVER, WHILE_SEEKING_GOAL, TOWARD_GOAL, ALWAYS = "never", "goal", "toward-goal", "always"
CLEARINGS = (NEVER, WHILE_SEEKING_GOAL, TOWARD_GOAL, ALWAYS)
# Patches wider than this either side are cleared: those heard from beyond about 0.9 m, where
# the cone is 0.4 m across, wider than a pillar or a door's edge. Nearer ones stay, since a
# pillar close beside the robot is what the specular ring fails to hear at a cone's edge
# (benchmarks/goal_openings.py measures goals and contacts with and without clearing).
CLEARED_ABOVE_M = 0.2
# `toward-goal` clears the beam nearest the goal's bearing and this many either side. On the
# goal tuning worlds (docs/results.md, *Openings through the memory*), with the labels then
# capped at the top speed, the goal's beam alone reached 39 goals of 84 at 0.06 contacts a
# minute; one either side as well, 50 at 0.47, nearly all of them among the most closely set
# pillars. With the tight arcs lifted the goal's beam alone reaches 44 at 0.36.
GOAL_BEAMS_EITHER_SIDE = 0
# Chosen on the tuning worlds (docs/results.md, *The echo memory*): 20 s kept the most
# competent runs.
# Odometry misplaces an echo heard 20 s ago by 3-6 cm (median) and one heard a minute ago by
# 7-11 cm, a quarter of a metre one time in twenty (benchmarks/memory_drift.py), and a minute
# did worse; 5 and 10 s forgot walls before the robot met them.
DEFAULT_WINDOW_S = 20.0
# Every echo the ring hears (4 m at most): nearer limits (2 and 3 m) did worse, since a
# far wall heard square on is the one a slanted approach later fails to hear.
DEFAULT_RANGE_M = 4.0
DEFAULT_PATCH_M = 0.3
MAX_WINDOW_S = 600.0
# Bounds that keep the memory's geometry finite, far beyond the reach of any sonar ring.
MAX_RANGE_M = 100.0
MAX_PATCH_M = 10.0


@dataclass(frozen=True, slots=True)
class MemoryConfig:
    """How the robot remembers echoes; recorded in every log session and FAM file."""

    kind: str = NONE
    window_s: float = DEFAULT_WINDOW_S  # echoes older than this are forgotten
    range_m: float = DEFAULT_RANGE_M  # echoes farther than this are not remembered
    patch_m: float = DEFAULT_PATCH_M  # a patch is at least this wide (patches only)
    clearing: str = TOWARD_GOAL  # when a live echo clears patches from its beam

    def __post_init__(self) -> None:
        if self.kind not in MEMORY_KINDS:
            raise BadInput(f"--memory {self.kind}: choose {', '.join(MEMORY_KINDS)}")
        if self.clearing not in CLEARINGS:
            raise BadInput(f"--memory-clearing {self.clearing}: choose {', '.join(CLEARINGS)}")
        for key, (flag, *_) in _LIMITS.items():
            _check_setting(key, getattr(self, key), flag)
        if self.kind == NONE:
            # Remembering nothing has no settings: every such memory is the same one.
            object.__setattr__(self, "window_s", DEFAULT_WINDOW_S)
            object.__setattr__(self, "range_m", DEFAULT_RANGE_M)
            object.__setattr__(self, "patch_m", DEFAULT_PATCH_M)
            object.__setattr__(self, "clearing", NEVER)

    @property
    def remembers(self) -> bool:
        return self.kind != NONE

    def clears(self, seeking_goal: bool) -> bool:
        """Whether live echoes clear wide patches, for a robot seeking a goal or not."""
        while_seeking = self.clearing in (WHILE_SEEKING_GOAL, TOWARD_GOAL)
        return self.clearing == ALWAYS or (while_seeking and seeking_goal)

    def opens_toward_goal(self, seeking_goal: bool) -> bool:
        """Whether the beams facing the goal meet no patch where they hear an echo."""
        return self.clearing == TOWARD_GOAL and seeking_goal

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any], omitted: MemoryConfig | None = None) -> MemoryConfig:
        """From a file's JSON; BadInput naming what is wrong. The settings `data` leaves out
        are `omitted`'s (a method file's: ours); without it, those of a file from before they
        were recorded: nothing remembered, never cleared."""
        if not isinstance(data, dict):
            raise BadInput(f"echo memory settings are not a JSON object: {data!r}")
        known = {"kind", "window_s", "range_m", "patch_m", "clearing"}
        unknown = sorted(set(data) - known)
        if unknown:
            raise BadInput(f"unknown echo memory setting {unknown[0]!r}")
        base = NO_MEMORY if omitted is None else omitted
        kind = data.get("kind", base.kind)
        if not isinstance(kind, str):
            raise BadInput(f"kind {kind!r} is not text: choose {', '.join(MEMORY_KINDS)}")
        # A file from before clearing was a choice never cleared (NO_MEMORY clears never).
        clearing = data.get("clearing", base.clearing)
        if clearing not in CLEARINGS:
            raise BadInput(f"clearing {clearing!r}: choose {', '.join(CLEARINGS)}")
        numbers = {key: data.get(key, getattr(base, key)) for key in _LIMITS}
        for key, value in numbers.items():
            _check_setting(key, value, key)  # named as the file names it
        floats = {key: float(value) for key, value in numbers.items()}
        return cls(kind, **floats, clearing=clearing)


# Each setting given as a number: its flag, its range (from more than or from, to) and unit.
_LIMITS: dict[str, tuple[str, float, float, str, bool]] = {
    "window_s": ("--memory-window", 0.0, MAX_WINDOW_S, "s", False),
    "range_m": ("--memory-range", 0.0, MAX_RANGE_M, "m", False),
    "patch_m": ("--memory-patch", 0.0, MAX_PATCH_M, "m", True),
}


def _check_setting(key: str, value: object, label: str) -> None:
    _, low, high, unit, low_allowed = _LIMITS[key]
    check_in_range(value, label, low, high, unit, low_allowed)


NO_MEMORY = MemoryConfig()
# What `tvl learn` remembers unless told otherwise (the paper's method remembers nothing):
# patches carried competence furthest toward the ideal sonar's on the tuning worlds, and
# clearing while seeking a goal, toward it most, opened the ways to goals among pillars.
DEFAULT_MEMORY = MemoryConfig(PATCHES)


@dataclass(frozen=True, slots=True)
class MemoryChoice:
    """The memory settings a user gave (None: not given), to apply over another memory: the
    one a FAM was trained through, a log was learnt through, or the default."""

    kind: str | None = None
    window_s: float | None = None
    range_m: float | None = None
    patch_m: float | None = None
    clearing: str | None = None

    def over(self, base: MemoryConfig) -> MemoryConfig:
        """`base` with every setting given here in its place. A memory turned on over none
        starts from ours: no memory's settings are placeholders, not choices."""
        given = {k: v for k, v in asdict(self).items() if v is not None}
        if not base.remembers and given.get("kind", NONE) != NONE:
            base = DEFAULT_MEMORY
        return MemoryConfig(**{**base.to_dict(), **given})

    @property
    def given(self) -> bool:
        return any(v is not None for v in asdict(self).values())


NOT_CHOSEN = MemoryChoice()
