"""`tvl explain RUN --contacts`: the contact autopsy of a run, from the simulator's truth.

The run's steps (a trace file's datasets, or the same columns recorded in memory) and its
world give each contact the facts analysis.autopsy judges it by: which obstacle it met, what
shape of it, whether any beam heard that obstacle in the seconds before, whether what the
FAM read held it, and what was driving.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.agent.engine import GOAL_RADIUS_M
from tvl_cli.agent.trace import Columns, before_each_step
from tvl_cli.agent.true_velocities import TrueVelocities
from tvl_cli.analysis.autopsy import (
    AUDIBLE_S,
    EDGE,
    PILLAR,
    RATING_S,
    REFLEX,
    RING,
    SLANT,
    SPINNING,
    Autopsy,
    Contact,
    ContactFacts,
    cause_of,
    goal_failure,
    time_by_class,
)
from tvl_cli.analysis.slow_time import slow_time_by_cause
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.core.contacts import BUMP, NEAR_MISS, near_miss_sonars, steps_beginning
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.method import DEFAULT, Method
from tvl_cli.core.ring import mm_to_ring
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.json_documents import document, input_file
from tvl_cli.io.logreader import file_sha256
from tvl_cli.io.runfile import read_run
from tvl_cli.sim.geometry import StaticGeometry, nearest_element, static_geometry
from tvl_cli.sim.sonar import SonarRing
from tvl_cli.sim.worldmap import WorldMap, parse_world

# A contact this near a wall's end meets the end itself: a convex edge or a free end.
EDGE_REACH_M = 0.05


# What the FAM read holds an obstacle when a beam it reads ranged the obstacle no farther than
# this beyond where it truly is in that beam: about the noise and the ring's minimum range.
GIVEN_TOLERANCE_M = 0.15


class _Hearing:
    """Which obstacle each beam heard at each step, cast again from the true poses with the
    run's sonar model (or, `ideal`, the nearest obstacle in each beam at any angle)."""

    def __init__(
        self,
        geometry: StaticGeometry,
        robot: RobotConfig,
        poses_before: np.ndarray,
        ideal: bool = False,
    ) -> None:
        self.geometry = geometry
        self.poses = poses_before  # (N, 3) true pose each reading was taken at
        sonar = replace(robot.sonar, ideal=True) if ideal else robot.sonar
        self._ring = SonarRing(sonar, robot.radius_m)
        self._cache: dict[int, tuple[np.ndarray, np.ndarray]] = {}

    def at(self, step: int) -> tuple[np.ndarray, np.ndarray]:
        """(16,) metres and (16,) obstacles the beams heard before `step`."""
        if step not in self._cache:
            x, y, theta = self.poses[step]
            self._cache[step] = self._ring.echo_sources(self.geometry, (x, y, theta))
        return self._cache[step]


def run_autopsy(
    world: WorldMap,
    robot: RobotConfig,
    columns: Columns,
    *,
    reflex_names: tuple[str, ...],
    trajectory_names: tuple[str, ...],
    table_sonars: dict[str, tuple[int, ...]] | None,
    goal_xy: tuple[float, float] | None,
    goal_reached: bool,
    method: Method = DEFAULT,
    fam: Fam | None = None,
    threshold: float = DEFAULT_THRESHOLD,
) -> Autopsy:
    """The autopsy of a run from its steps' columns (agent.trace names them).

    `table_sonars` names, for each trajectory, the sonars its FAM table reads (facing ahead);
    None counts every sonar as read. `method` gives the labels true velocities are told in
    (the oracle's, agent.true_velocities); `fam`, the run's, the experience of its ratings
    and what it would have rated on the live ring; `threshold`, the run's, which ways were
    fast.
    """
    dt = robot.control_period_s
    pose = columns["pose"]  # (N, 3) true pose after each step
    poses_before = before_each_step(pose, world.start)  # (N, 3)
    every = tuple(range(robot.sonar.count))
    sonars_of = {
        j: (table_sonars or {}).get(name, every) for j, name in enumerate(trajectory_names)
    }
    truth = TrueVelocities(world, robot, method)
    judge = _Contacts(world, robot, columns, poses_before, fam, sonars_of, truth)
    found = [(int(s), BUMP) for s in steps_beginning(columns["events"], BUMP)]
    found += [(int(s), NEAR_MISS) for s in steps_beginning(columns["events"], NEAR_MISS)]
    contacts = []
    for event_step, event in sorted(found):
        facts = judge.facts(event_step, event, reflex_names, trajectory_names)
        if facts is not None:
            contacts.append(Contact(facts, cause_of(facts)))
    time_s = time_by_class(columns["speed_mps"], columns["turn_radps"], columns["events"], dt)
    failure, closest = None, None
    if goal_xy is not None and not goal_reached:
        failure, closest = goal_failure(pose[:, :2], goal_xy, GOAL_RADIUS_M, time_s, dt)
    slow_s = slow_time_by_cause(
        robot, threshold, columns, poses_before, lambda pose: truth.in_view(pose, 0), fam
    )
    return Autopsy(tuple(contacts), time_s, failure, closest, slow_s)


class _Contacts:
    """The facts of a run's contacts, from its steps and the simulator's truth: where each
    began, what it met, whether a beam heard that before, whether what the FAM read held it,
    and what was driving."""

    def __init__(
        self,
        world: WorldMap,
        robot: RobotConfig,
        columns: Columns,
        poses_before: np.ndarray,
        fam: Fam | None,
        sonars_of: dict[int, tuple[int, ...]],
        truth: TrueVelocities,
    ) -> None:
        self._dt = robot.control_period_s
        self._columns = columns
        self._poses_before = poses_before  # (N, 3) true pose each reading was taken at
        self._sonars_of = sonars_of  # each trajectory's table's sonars, facing ahead
        self._read = np.asarray(columns["ring_mm"].any(axis=1))  # (N,) the ring was read
        self._ring_m = mm_to_ring(columns["ring_mm"])  # (N, 16) metres
        self._geometry = static_geometry(world)
        self._hearing = _Hearing(self._geometry, robot, poses_before)
        self._truth = _Hearing(self._geometry, robot, poses_before, ideal=True)
        # (N, 16) metres: the ring as the FAM read it
        self._fam_read = mm_to_ring(columns.get("perceived_mm", columns["ring_mm"]))
        self._min_range_m = robot.sonar.min_range_m
        self._near_sonars = np.array(near_miss_sonars(robot.sonar.count))  # (s,) sonars
        # (N,) readings with a beam ahead inside the ring's minimum range
        self._blind = self._read & np.asarray(
            (self._ring_m[:, self._near_sonars] <= self._min_range_m).any(axis=1)
        )
        self._audible_steps = max(1, round(AUDIBLE_S / self._dt))
        self._rating_steps = max(1, round(RATING_S / self._dt))
        # (N,) steps the policy chose, seeing the ring
        self._decided = self._read & (columns["choice"] >= 0)
        self._ratings = _Ratings(truth, columns, poses_before, self._fam_read, fam)

    def facts(
        self,
        event_step: int,
        event: str,
        reflex_names: tuple[str, ...],
        trajectory_names: tuple[str, ...],
    ) -> ContactFacts | None:
        """The facts of the contact counted at `event_step`; None if nothing was there."""
        began, moved, where, obstacle = self._onset(event_step, event)
        if obstacle < 0:
            return None
        # The choices that led to it: those of the seconds before, up to its beginning.
        first_choice = max(0, moved - self._rating_steps + 1)
        choices = np.flatnonzero(self._decided[first_choice : moved + 1]) + first_choice
        held_m = _held_at(
            self._truth, choices, self._fam_read, self._columns, obstacle, self._sonars_of
        )
        rated, true, experience = (
            self._ratings.of(int(choices[-1])) if len(choices) else (None,) * 3
        )
        return ContactFacts(
            step=began,
            time_s=(began + 1) * self._dt,
            event=event,
            obstacle=_shape(self._geometry, obstacle, where),
            **_driver(self._columns, moved, reflex_names, trajectory_names),
            heard=self._heard(began, obstacle),
            given=held_m is not None,
            given_beyond_blind_zone=held_m is not None and held_m > self._min_range_m,
            rated_mps=rated,
            true_mps=true,
            experience=experience,
        )

    def _onset(self, event_step: int, event: str) -> tuple[int, int, np.ndarray, int]:
        """The step the contact began, the step whose command drove into it, where the body
        was (x, y, theta) and the obstacle it met (-1: none)."""
        if event == BUMP:
            # It began on the step that closed the bump sensor, touching where it ended: that
            # step's command drove into it.
            where = self._columns["pose"][event_step]
            obstacle, _ = nearest_element(self._geometry, where[0], where[1])
            return event_step, event_step, where, obstacle
        # Counted when the approach ended; it began at the approach's first blind reading,
        # taken after the step before it drove there (the step of the reading itself is
        # already the reflexes' answer to it).
        began = event_step
        while began > 0 and self._blind[began - 1]:
            began -= 1
        began = min(began, len(self._poses_before) - 1)
        obstacle = _blind_obstacle(self._hearing, began, self._ring_m[began], self._near_sonars)
        return began, max(began - 1, 0), self._poses_before[began], obstacle

    def _heard(self, began: int, obstacle: int) -> bool:
        """Whether a beam heard the obstacle, beyond the ring's minimum range, in the seconds
        before the contact began."""
        heard = False
        for step in range(max(0, began - self._audible_steps + 1), began + 1):
            if self._read[step]:
                ranges, sources = self._hearing.at(step)
                heard |= bool(((sources == obstacle) & (ranges > self._min_range_m)).any())
        return heard


class _Ratings:
    """How a choice rated the way it chose, how fast that way truly was, and the experience
    behind the rating."""

    def __init__(
        self,
        truth: TrueVelocities,
        columns: Columns,
        poses_before: np.ndarray,
        fam_read: np.ndarray,
        fam: Fam | None,
    ) -> None:
        self._truth = truth
        self._columns = columns
        self._poses = poses_before
        self._fam_read = fam_read
        self._fam = fam

    def of(self, step: int) -> tuple[float, float, float | None]:
        """At the choice of `step`: the rating (m/s), the true velocity, the experience."""
        rotation, chosen = int(self._columns["rotation"][step]), int(self._columns["choice"][step])
        x, y, theta = self._poses[step]
        true = self._truth.in_view((float(x), float(y), float(theta)), rotation % 16)[chosen]
        experience = (
            None
            if self._fam is None
            else float(self._fam.perceive(self._fam_read[step])[1][rotation % 16, chosen])
        )
        return float(self._columns["velocities"][step, chosen]), float(true), experience


def _blind_obstacle(
    hearing: _Hearing, step: int, ring_m: np.ndarray, near_sonars: np.ndarray
) -> int:
    """The obstacle inside the blind zone ahead at `step`: the one the nearest front beam
    heard, else (a beam that heard it only through noise) the one nearest the body."""
    _, sources = hearing.at(step)
    beam = near_sonars[int(np.argmin(ring_m[near_sonars]))]
    if sources[beam] >= 0:
        return int(sources[beam])
    x, y, _ = hearing.poses[step]
    return nearest_element(hearing.geometry, x, y)[0]


def _shape(geometry: StaticGeometry, element: int, where: np.ndarray) -> str:
    """SLANT, EDGE, PILLAR or RING: what of the obstacle a body centred at `where` meets."""
    kind = geometry.element_kind(element)
    if kind == "disc":
        return PILLAR
    if kind == "ring":
        return RING
    x1, y1, x2, y2 = geometry.segments[element]
    dx, dy = x2 - x1, y2 - y1
    length = math.hypot(dx, dy)
    along = ((where[0] - x1) * dx + (where[1] - y1) * dy) / length  # metres from the start
    side = math.copysign(1.0, dx * (where[1] - y1) - dy * (where[0] - x1))
    for end, at_m in ((0, 0.0), (1, length)):
        at_end = abs(along - at_m) <= EDGE_REACH_M or (along < 0.0 if end == 0 else along > length)
        # Where the other wall at this end leaves on the robot's side the corner is concave,
        # and echoes from anywhere in a beam; else it is a convex edge or a free end.
        if at_end and geometry.corner_sides[element, end] != side:
            return EDGE
    return SLANT


def _driver(
    columns: Columns, step: int, reflex_names: tuple[str, ...], names: tuple[str, ...]
) -> dict[str, Any]:
    reflex = int(columns["reflex"][step])
    speed, turn = float(columns["speed_mps"][step]), float(columns["turn_radps"][step])
    trajectory = int(columns["trajectory"][step])
    if reflex >= 0:
        return {"driver": REFLEX, "reflex": reflex_names[reflex], "trajectory": None}
    if speed == 0.0 and turn != 0.0:
        return {"driver": SPINNING, "reflex": None, "trajectory": None}
    return {
        "driver": "policy",
        "reflex": None,
        "trajectory": names[trajectory] if trajectory >= 0 else None,
    }


def _held_at(
    truth: _Hearing,
    choices: np.ndarray,
    fam_read: np.ndarray,
    columns: Columns,
    obstacle: int,
    sonars_of: dict[int, tuple[int, ...]],
) -> float | None:
    """The farthest range at which what the FAM read at the `choices` (steps) held the
    obstacle; None if it never did. It is held in a beam that the chosen trajectory's table
    reads (in the view chosen in) where the obstacle is the nearest thing, when the ring the
    FAM read ranged it no farther than it truly is."""
    farthest = None
    for step in choices:
        ranges, sources = truth.at(int(step))
        rotation = int(columns["rotation"][step])
        read = (np.array(sonars_of[int(columns["choice"][step])]) + rotation) % len(ranges)
        held = (sources[read] == obstacle) & (
            fam_read[step, read] <= ranges[read] + GIVEN_TOLERANCE_M
        )
        if held.any():
            at_m = float(fam_read[step, read[held]].min())
            farthest = at_m if farthest is None else max(farthest, at_m)
    return farthest


@dataclass(frozen=True, slots=True)
class TraceAutopsy:
    """Why each contact of a recorded run happened (`tvl explain --contacts`)."""

    run: Path
    autopsy: Autopsy

    def document(self) -> dict[str, Any]:
        inputs = {"run": input_file(self.run), "fam": None, "contacts": True}
        return document("explain", inputs, step=None, autopsy=self.autopsy.to_dict())


def trace_autopsy(path: Path) -> TraceAutopsy:
    """The autopsy of a run trace file."""
    trace = read_run(path)
    if not trace.has_decisions:
        raise BadInput(f"{path}: a format_version 1 trace records no events to explain")
    parameters = trace.parameters
    robot = RobotConfig.from_dict(trace.robot_config)
    world = parse_world(trace.world_text, str(path))
    goal = parameters.get("goal")
    found = run_autopsy(
        world,
        robot,
        trace.arrays,
        reflex_names=trace.reflex_names,
        trajectory_names=tuple(t.name for t in robot.trajectories),
        table_sonars=parameters.get("sonars_read"),
        goal_xy=(float(goal[0]), float(goal[1])) if goal else None,
        goal_reached=bool(trace.metrics.get("goal_reached")),
        method=trace.method,
        fam=_fam_if_found(parameters),
        threshold=float(parameters.get("threshold", DEFAULT_THRESHOLD)),
    )
    return TraceAutopsy(path, found)


def _fam_if_found(parameters: dict[str, Any]) -> Fam | None:
    """The FAM the run was driven with, if it is still where the trace says, unchanged; else
    none (its ratings' experience goes unsaid)."""
    named = Path(str(parameters.get("fam", "")))
    if not named.is_file() or file_sha256(named) != parameters.get("fam_sha256"):
        return None
    try:
        return read_fam(named).fam
    except BadInput:
        return None
