"""The contact autopsy: why each contact of a run happened, and where the run's time went.

A contact (a collision or a near miss, core.contacts) gets one cause, the first that fits:
- `reflex`: a reflex was driving when it began (backing off has no sonar behind);
- `spin`: the robot was turning on the spot;
- `unheard-slant`, `unheard-edge`, `unheard-pillar`, `unheard-ring`: no beam heard the obstacle
  beyond the ring's blind zone in the last AUDIBLE_S seconds (at most as it touched): a smooth
  wall met at a slant, a convex edge (a block's corner, a thin wall's end), a pillar or a
  ring wall the beams missed. The sensor's limit;
- `not-given`: it was heard, but what the FAM read at the choices of the last RATING_S seconds
  never held it where the chosen trajectory's table reads (no echo memory, or it had been
  forgotten);
- `blind-zone`: the FAM read it, but only inside the blind zone, where the ring cannot tell
  near from touching;
- `rated-fast`: the FAM read it beyond the blind zone, and still rated the way fast enough to
  drive into it: what was learnt is at fault;
- `other`: none of these.

A step the policy drove slower than competence asks (FAST_DRIVE_MPS), spins included, gets
one cause too (SLOW_CAUSES, slow_cause). It is judged straight ahead, in the view the choice
looks at first and drives on in when it finds a fast way there; only when it finds none does
it turn:
- `tight`: no trajectory ahead was truly fast (its true velocity, from the map, under
  threshold x its maximum): slowing or turning was right;
- `rule`: a way ahead truly fast was rated fast on what the FAM read, and the behaviour's
  rule (the goal's bearing, the wall's side, a way a reflex left out) took a slower one;
- `memory`: every way ahead truly fast was rated slow on what the FAM read, and one of them
  fast on the live ring alone: remembered echoes closed it;
- `learnt`: every way ahead truly fast was rated slow on the live ring too: what was learnt;
- `unrated`: no FAM at hand to tell the last two apart.

The facts come from the simulator's ground truth (commands.contact_autopsy); the rules are here.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from tvl_cli.core.contacts import TRAPPED, steps_beginning

# How far back a contact's obstacle is looked for among the echoes: the "last few seconds"
# in which the robot could have heard what it was about to meet.
AUDIBLE_S = 5.0
# The choices that should have rated a contact's way slow: a trajectory stays fast (at the
# default threshold and labels) until its collision point is 0.6 m (T3) to 1.6 m (T0) ahead,
# two to three seconds at the speeds it is driven at.
RATING_S = 2.0

REFLEX, SPINNING = "reflex", "spin"
UNHEARD = "unheard"
BLIND_ZONE, NOT_GIVEN, RATED_FAST, OTHER = "blind-zone", "not-given", "rated-fast", "other"
# Obstacle shapes an unheard contact is told apart by.
SLANT, EDGE, PILLAR, RING = "slant", "edge", "pillar", "ring"
CAUSES = (
    REFLEX,
    SPINNING,
    *(f"{UNHEARD}-{shape}" for shape in (SLANT, EDGE, PILLAR, RING)),
    NOT_GIVEN,
    BLIND_ZONE,
    RATED_FAST,
    OTHER,
)

# Where the time of a run went, one class a control step.
DRIVE_FAST, DRIVE_MEDIUM, DRIVE_SLOW = "drive >= 0.3 m/s", "drive 0.2-0.3 m/s", "drive < 0.2 m/s"
TIME_CLASSES = (DRIVE_FAST, DRIVE_MEDIUM, DRIVE_SLOW, "spin", "trapped", "backoff", "stopped")
# The speed competence asks of a run (core.competence) splits the driving.
FAST_DRIVE_MPS = 0.3
MEDIUM_DRIVE_MPS = 0.2

# Why the policy drove slowly (the module's docstring says what each means).
TIGHT, RULE, MEMORY, LEARNT, UNRATED = "tight", "rule", "memory", "learnt", "unrated"
SLOW_CAUSES = (TIGHT, RULE, MEMORY, LEARNT, UNRATED)

# Why a goal run ended without its goal.
DRIFT, TRAPPED_GOAL, STALLED, WANDERED = "drift", "trapped", "stalled", "wandered"
GOAL_FAILURES = (DRIFT, TRAPPED_GOAL, STALLED, WANDERED)
# A run that moved less than this in its last minute, net, was stalled (at a doorway, say).
STALLED_M = 0.5
STALLED_WINDOW_S = 60.0


@dataclass(frozen=True, slots=True)
class ContactFacts:
    """What the ground truth says of one contact."""

    step: int  # the step it began on (a near miss: its approach's first step)
    time_s: float  # simulated seconds at the end of that step
    event: str  # core.contacts BUMP or NEAR_MISS
    obstacle: str  # SLANT (a wall's face), EDGE, PILLAR or RING
    driver: str  # "policy", REFLEX or SPINNING: what was driving when it began
    reflex: str | None  # the reflex, when one was driving
    trajectory: str | None  # the trajectory being driven, if one was
    heard: bool  # a beam heard it beyond the blind zone in the AUDIBLE_S before
    given: bool  # what the FAM read at a choice in the RATING_S before held it
    given_beyond_blind_zone: bool  # ... farther than the blind zone
    # The last choice of the RATING_S before, if there was one: the way it rated (m/s), how
    # fast that way truly was (the oracle velocity, from the map), and the FAM's experience
    # of what it read there (None where the FAM is not at hand).
    rated_mps: float | None = None
    true_mps: float | None = None
    experience: float | None = None


def cause_of(facts: ContactFacts) -> str:
    """The first cause that fits, in CAUSES order."""
    if facts.driver == REFLEX:
        return REFLEX
    if facts.driver == SPINNING:
        return SPINNING
    if not facts.heard:
        return f"{UNHEARD}-{facts.obstacle}"
    if not facts.given:
        return NOT_GIVEN
    if not facts.given_beyond_blind_zone:
        return BLIND_ZONE
    if facts.driver == "policy":
        return RATED_FAST
    return OTHER


@dataclass(frozen=True, slots=True)
class Contact:
    facts: ContactFacts
    cause: str

    def to_dict(self) -> dict[str, Any]:
        return {**asdict(self.facts), "cause": self.cause}


@dataclass(frozen=True, slots=True)
class Autopsy:
    """One run: its contacts with their causes, its time by class, and for a goal run that
    missed its goal, why."""

    contacts: tuple[Contact, ...]
    time_s: dict[str, float]  # TIME_CLASSES -> simulated seconds
    goal_failure: str | None = None  # one of GOAL_FAILURES; None if no goal was missed
    goal_closest_m: float | None = None  # the truth's closest approach to the goal
    # SLOW_CAUSES -> simulated seconds the policy drove slowly for it
    slow_time_s: dict[str, float] = field(default_factory=lambda: dict.fromkeys(SLOW_CAUSES, 0.0))
    causes: dict[str, int] = field(init=False)

    def __post_init__(self) -> None:
        counted = Counter(c.cause for c in self.contacts)
        object.__setattr__(self, "causes", {cause: counted[cause] for cause in CAUSES})

    def to_dict(self) -> dict[str, Any]:
        return {
            "contacts": [c.to_dict() for c in self.contacts],
            # Lists of records: a cause or a class of time is a name, not a JSON key.
            "causes": [{"cause": c, "contacts": n} for c, n in self.causes.items()],
            "time": [{"class": c, "time_s": t} for c, t in self.time_s.items()],
            "goal_failure": self.goal_failure,
            "goal_closest_m": self.goal_closest_m,
            "slow_time": [{"cause": c, "time_s": t} for c, t in self.slow_time_s.items()],
        }


def slow_cause(truly_fast: np.ndarray, read_fast: np.ndarray, live_fast: np.ndarray | None) -> str:
    """Why a slow step was slow, from which trajectories ahead (T,) were truly fast, rated
    fast on what the FAM read, and rated fast on the live ring alone (None: no FAM)."""
    if not truly_fast.any():
        return TIGHT
    if (truly_fast & read_fast).any():
        return RULE
    if live_fast is None:
        return UNRATED
    if (truly_fast & live_fast).any():
        return MEMORY
    return LEARNT


def time_by_class(
    speed_mps: np.ndarray, turn_radps: np.ndarray, events: np.ndarray, dt_s: float
) -> dict[str, float]:
    """Simulated seconds of each TIME_CLASSES class, from the commands of each step (N,) and
    the event bits (N,) each began. A spin is trapped from the step a trapped event began
    until the robot stops spinning."""
    spinning = (speed_mps == 0.0) & (turn_radps != 0.0)
    trapped = np.zeros(len(speed_mps), dtype=bool)
    starts = set(steps_beginning(events, TRAPPED).tolist())
    inside = False
    for i in range(len(speed_mps)):
        inside = (inside or i in starts) and bool(spinning[i])
        trapped[i] = inside
    forward = speed_mps > 0.0
    steps = {
        DRIVE_FAST: forward & (speed_mps >= FAST_DRIVE_MPS),
        DRIVE_MEDIUM: forward & (speed_mps >= MEDIUM_DRIVE_MPS) & (speed_mps < FAST_DRIVE_MPS),
        DRIVE_SLOW: forward & (speed_mps < MEDIUM_DRIVE_MPS),
        "spin": spinning & ~trapped,
        "trapped": trapped,
        "backoff": speed_mps < 0.0,
        "stopped": (speed_mps == 0.0) & (turn_radps == 0.0),
    }
    return {name: float(mask.sum()) * dt_s for name, mask in steps.items()}


def goal_failure(
    true_xy: np.ndarray,
    goal_xy: tuple[float, float],
    goal_radius_m: float,
    time_s: dict[str, float],
    dt_s: float,
) -> tuple[str, float]:
    """Why a goal run that ran out of time missed its goal, from its true path (N, 2) metres,
    and the truth's closest approach to the goal (m)."""
    distance = np.hypot(true_xy[:, 0] - goal_xy[0], true_xy[:, 1] - goal_xy[1])  # (N,) m
    closest = float(distance.min()) if len(distance) else float("inf")
    total = sum(time_s.values())
    last = true_xy[-max(1, round(STALLED_WINDOW_S / dt_s)) :]
    moved = float(np.hypot(*(last[-1] - last[0]))) if len(last) else 0.0
    if closest <= goal_radius_m:
        return DRIFT, closest  # it was there, but odometry placed it elsewhere
    if total and (time_s["trapped"] + time_s["spin"]) >= 0.5 * total:
        return TRAPPED_GOAL, closest
    if moved < STALLED_M:
        return STALLED, closest
    return WANDERED, closest


# A rule whose experience is under one exemplar's full firing was barely trained.
LITTLE_EXPERIENCE = 1.0


def tally(autopsies: Iterable[dict[str, Any]]) -> dict[str, Any]:
    """Autopsies (as `Autopsy.to_dict` gives them) summed: contacts by cause, seconds by
    time class and slow seconds by cause (none in rows made before it was told), goal
    failures by reason, and of the rated-fast contacts what the FAM had
    learnt there: the median true velocity of the way it rated fast, the share it had
    under one exemplar's experience of, and how many were met on each trajectory (most first;
    rows made before they kept it say none)."""
    causes: Counter[str] = Counter()
    time_s: Counter[str] = Counter()
    slow_s: Counter[str] = Counter()
    failures: Counter[str] = Counter()
    rated_fast = []
    for autopsy in autopsies:
        causes.update({row["cause"]: row["contacts"] for row in autopsy["causes"]})
        time_s.update({row["class"]: row["time_s"] for row in autopsy["time"]})
        slow_s.update({row["cause"]: row["time_s"] for row in autopsy.get("slow_time", ())})
        if autopsy["goal_failure"] is not None:
            failures[autopsy["goal_failure"]] += 1
        rated_fast += [c for c in autopsy["contacts"] if c["cause"] == RATED_FAST]
    true = [c["true_mps"] for c in rated_fast if c.get("true_mps") is not None]
    rated = [c["rated_mps"] for c in rated_fast if c.get("rated_mps") is not None]
    known = [c["experience"] for c in rated_fast if c.get("experience") is not None]
    driven = Counter(c["trajectory"] for c in rated_fast if c.get("trajectory") is not None)
    return {
        "causes": {cause: causes[cause] for cause in CAUSES},
        "time_s": {name: time_s[name] for name in TIME_CLASSES},
        "slow_time_s": {cause: slow_s[cause] for cause in SLOW_CAUSES},
        "goal_failures": {reason: failures[reason] for reason in GOAL_FAILURES},
        "rated_fast": {
            "contacts": len(rated_fast),
            "median_true_mps": float(np.median(true)) if true else None,
            "median_rated_mps": float(np.median(rated)) if rated else None,
            "untrained_share": (
                sum(e < LITTLE_EXPERIENCE for e in known) / len(known) if known else None
            ),
            # A list of records: a trajectory is a name, not a JSON key.
            "by_trajectory": [
                {"trajectory": name, "contacts": n}
                for name, n in sorted(driven.items(), key=lambda item: (-item[1], item[0]))
            ],
        },
    }
