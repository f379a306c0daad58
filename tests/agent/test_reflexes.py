"""Each reflex switched on alone, on a real simulated robot, changes what it should."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from tvl_cli.agent.drive import Step
from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.policy import Decision, LazyRing, Observation
from tvl_cli.agent.reflexes import (
    BLOCKED_S,
    FIRST_ESCAPE_S,
    PROGRESS_M,
    REFLEXES,
    STACK_ORDER,
    STALLED_S,
    BlockedWays,
    GoalWard,
    TieToLastTurn,
    WallEscape,
    WallStart,
    wrap,
)
from tvl_cli.agent.tvl import TvlPolicy
from tvl_cli.core.drive_command import Command
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT, REFLEX_NAMES, parse_reflexes
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.worldmap import parse_world

ROBOT = RobotConfig()
HALL = parse_world(
    "version: 1\nname: hall\ncell: 0.25\n\n"
    + "#" * 32
    + "\n"
    + ("#" + "." * 30 + "#\n") * 2
    + "#.>"
    + "." * 28
    + "#\n"
    + ("#" + "." * 30 + "#\n") * 4
    + "#" * 32
    + "\n",
    "hall",
)
# A straight passage 7 m long and 0.75 m wide, the robot in its middle facing along it.
PASSAGE = parse_world(
    "version: 1\nname: passage\ncell: 0.25\n\n"
    + "#" * 30
    + "\n"
    + ("#" + "." * 28 + "#\n")
    + ("#.>" + "." * 26 + "#\n")
    + ("#" + "." * 28 + "#\n")
    + "#" * 30
    + "\n",
    "passage",
)
# Straight down the hall at T0's 0.6 m/s, the body's edge meets the east wall after 11.5 s.
TO_THE_END_WALL_MIN = 12.0 / 60.0


def fast_everywhere_fam() -> Fam:
    """A FAM that perceives every trajectory at its maximum, whatever the ring reads."""
    return Fam(SINGLE, [t.name for t in ROBOT.trajectories], max(ROBOT.v_max_mps))


def run(reflexes: tuple[str, ...], minutes: float = TO_THE_END_WALL_MIN, world=HALL):
    steps: list[Step] = []
    metrics = behave(
        world,
        ROBOT,
        fast_everywhere_fam(),
        "avoid",
        minutes=minutes,
        seed=1,
        on_step=steps.append,
        method=replace(DEFAULT, reflexes=reflexes, memory=NO_MEMORY),
    )
    return metrics, steps


def test_near_miss_alone_backs_off_before_contact() -> None:
    metrics, steps = run(("near-miss",))
    # Alone it backs off and, every way still perceived fast, drives at the wall again.
    assert metrics.collisions == 0
    assert metrics.near_misses == metrics.backoffs >= 1
    assert {s.decision.reflex for s in steps if s.decision.command.linear_mps < 0} == {"near-miss"}


def test_without_it_the_same_run_meets_the_wall() -> None:
    metrics, _ = run(())
    assert (metrics.collisions, metrics.near_misses, metrics.backoffs) == (1, 0, 0)


def test_bump_alone_backs_off_after_the_contact() -> None:
    metrics, steps = run(("bump",), TO_THE_END_WALL_MIN + 1.0 / 60.0)
    assert metrics.collisions >= 1 and metrics.backoffs >= 1
    first_bump = next(i for i, s in enumerate(steps) if "bump" in s.events)
    assert steps[first_bump + 1].decision.reflex == "bump"
    assert steps[first_bump + 1].decision.command.linear_mps < 0


def test_walls_alongside_in_a_narrow_passage_are_no_near_miss() -> None:
    # 0.75 m wide: 0.175 m either side of the body, just outside the sonars' blind zone.
    metrics, _ = run(STACK_ORDER, 5.0 / 60.0, PASSAGE)
    assert (metrics.near_misses, metrics.collisions, metrics.backoffs) == (0, 0, 0)
    assert metrics.distance_m == pytest.approx(0.6 * 5.0, abs=0.01)


def test_blocked_ways_send_the_robot_off_away_from_the_way_it_met_the_wall() -> None:
    _, steps = run(("blocked-ways", "near-miss"), TO_THE_END_WALL_MIN + 2.0 / 60.0)
    reversing = next(i for i, s in enumerate(steps) if s.decision.command.linear_mps < 0)
    after = next(s for s in steps[reversing:] if s.decision.command.linear_mps > 0)
    # Every trajectory is fast, yet the robot (which met the wall driving east, heading 0)
    # turns on the spot until what it follows sets off more than 45 degrees away from east.
    assert abs(math.remainder(after.pose[2], 2 * math.pi)) > math.radians(40)


def test_without_blocked_ways_it_sets_off_the_way_it_came() -> None:
    _, steps = run(("near-miss",), TO_THE_END_WALL_MIN + 2.0 / 60.0)
    reversing = next(i for i, s in enumerate(steps) if s.decision.command.linear_mps < 0)
    after = next(s for s in steps[reversing:] if s.decision.command.linear_mps > 0)
    assert abs(math.remainder(after.pose[2], 2 * math.pi)) < math.radians(5)


def test_a_blocked_way_is_held_by_odometry_until_two_seconds_after_backing_off() -> None:
    steps: list[Step] = []
    from tvl_cli.agent.drive import drive
    from tvl_cli.agent.tvl import TvlPolicy
    from tvl_cli.sim.robot import Simulator

    sim = Simulator(HALL, ROBOT, np.random.default_rng(1))
    policy = wrap(
        TvlPolicy(fast_everywhere_fam(), ROBOT, "avoid", 0.85),
        ("blocked-ways", "near-miss"),
        ROBOT,
        "avoid",
    )
    assert isinstance(policy, BlockedWays)
    drive(sim, policy, TO_THE_END_WALL_MIN, on_step=steps.append)
    event = next(i for i, s in enumerate(steps) if s.decision.command.linear_mps < 0)
    reversing = sum(1 for s in steps[event:] if s.decision.command.linear_mps < 0)
    (way,) = policy.blocked_ways
    before = steps[event - 1]  # the step that drove into the blind zone
    assert way.heading_rad == before.odometry[2] != before.pose[2]
    dt = ROBOT.control_period_s
    assert way.until_s == pytest.approx((event + reversing) * dt + BLOCKED_S)


class Recording:
    """An inner policy that remembers the advice it was given and turns as it is told."""

    def __init__(self, decisions: list[Decision]) -> None:
        self.decisions = decisions
        self.tie_sides: list[int] = []
        self.behaviours: list[str] = []
        self.preferences: list[object] = []

    def decide(self, obs: Observation) -> Decision:
        self.tie_sides.append(obs.tie_side)
        self.behaviours.append(obs.behaviour)
        self.preferences.append(obs.prefer)
        return self.decisions.pop(0) if self.decisions else Decision(Command(0.3, 0.0))

    def interrupt(self) -> None:
        pass


def _obs(
    time_s: float = 0.0,
    x_m: float = 0.0,
    goal_xy: tuple[float, float] | None = None,
) -> Observation:
    ring = LazyRing(lambda: np.full(16, 4.0))
    return Observation(time_s, ring, (x_m, 0.0, 0.0), False, goal_xy=goal_xy)


def _advice_each_second(reflex: WallEscape, inner: Recording, xs: list[float]) -> list[str]:
    """The behaviour advised at each whole second, the robot at x = xs[t] metres (by
    odometry), its goal 5 m along x."""
    for t, x in enumerate(xs):
        reflex.decide(_obs(float(t), x, (5.0, 0.0)))
    return inner.behaviours


def test_a_goal_stalled_escapes_along_walls_both_ways_for_longer_and_longer() -> None:
    inner = Recording([])
    stalled = int(STALLED_S)
    first = int(FIRST_ESCAPE_S)
    advice = _advice_each_second(WallEscape(inner, ROBOT, "goal"), inner, [0.0] * 120)
    # Seeking the goal until it has come no nearer for STALLED_S; then the left wall for
    # FIRST_ESCAPE_S; the goal again for STALLED_S; then the right wall twice as long.
    assert advice[:stalled] == [""] * stalled
    assert advice[stalled : stalled + first] == ["wall-left"] * first
    second = 2 * stalled + first
    assert advice[stalled + first : second] == [""] * stalled
    assert advice[second : second + 2 * first] == ["wall-right"] * (2 * first)
    assert advice[second + 2 * first] == ""


def test_an_escape_ends_once_the_robot_is_nearer_the_goal_than_ever() -> None:
    inner = Recording([])
    stalled = int(STALLED_S)
    # Stalled at x = 0, then the wall leads 0.1 m nearer each second.
    xs = [0.0] * (stalled + 1) + [0.1 * k for k in range(1, 30)]
    advice = _advice_each_second(WallEscape(inner, ROBOT, "goal"), inner, xs)
    nearer = next(t for t, x in enumerate(xs) if x >= PROGRESS_M - 1e-9)
    assert advice[stalled:nearer] == ["wall-left"] * (nearer - stalled)
    assert set(advice[nearer:]) == {""}


def test_progress_towards_the_goal_never_escapes() -> None:
    inner = Recording([])
    xs = [0.05 * t for t in range(90)]  # 0.3 m nearer every 6 s
    assert set(_advice_each_second(WallEscape(inner, ROBOT, "goal"), inner, xs)) == {""}


@pytest.mark.parametrize("behaviour", ["avoid", "wall-left", "goal"])
def test_the_escape_leaves_other_behaviours_and_goalless_runs_alone(behaviour: str) -> None:
    inner = Recording([])
    reflex = WallEscape(inner, ROBOT, behaviour)
    goal = (5.0, 0.0) if behaviour != "goal" else None
    for t in range(60):
        reflex.decide(_obs(float(t), 0.0, goal))
    assert set(inner.behaviours) == {""}


class Perceiving:
    """Perceives the same velocities (16, 7) m/s whatever the ring reads."""

    def __init__(self, velocities: np.ndarray) -> None:
        self.velocities = velocities

    def perceive(self, ring_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self.velocities, np.ones_like(self.velocities)

    def perceive_ahead(self, ring_m: np.ndarray) -> np.ndarray:
        return self.velocities[0]


# Facing along x with the goal 45 degrees to the left: ahead only T3R is fast, which half a
# metre along heads 102 degrees off the goal; two sonars to the left, T0 heads straight at it.
T3R, T0, LEFT_TWO = 6, 3, 2
GOAL_LEFT = (1.0, 1.0)


def _one_choice(reflexes: tuple[str, ...], behaviour: str = "goal") -> Decision:
    velocities = np.zeros((16, len(ROBOT.trajectories)))
    velocities[0, T3R] = ROBOT.v_max_mps[T3R]
    velocities[LEFT_TWO, T0] = ROBOT.v_max_mps[T0]
    policy = TvlPolicy(Perceiving(velocities), ROBOT, behaviour, 0.85)
    goal = GOAL_LEFT if behaviour == "goal" else None
    return wrap(policy, reflexes, ROBOT, behaviour).decide(_obs(goal_xy=goal))


def test_the_papers_goal_rule_takes_the_fast_way_ahead_that_leads_off() -> None:
    decision = _one_choice(())
    assert (decision.rotation, decision.choice) == (0, T3R)


def test_goal_ward_turns_to_face_a_fast_way_toward_the_goal_instead() -> None:
    decision = _one_choice(("goal-ward",))
    assert (decision.rotation, decision.choice) == (LEFT_TWO, T0)
    assert decision.trajectory == -1  # it spins to face that view first


@pytest.mark.parametrize("behaviour", ["avoid", "wall-left"])
def test_goal_ward_leaves_other_behaviours_to_the_rule(behaviour: str) -> None:
    with_it, without = _one_choice(("goal-ward",), behaviour), _one_choice((), behaviour)
    assert (with_it.rotation, with_it.choice) == (without.rotation, without.choice)


def test_goal_ward_prefers_the_ways_heading_within_90_degrees_of_the_goal() -> None:
    inner = Recording([])
    GoalWard(inner, ROBOT, "goal").decide(_obs(goal_xy=GOAL_LEFT))
    (prefer,) = inner.preferences
    degrees = np.radians([[45.0, 135.0, 134.0, -44.0, -46.0, 180.0]])
    assert prefer(degrees).tolist() == [[True, True, True, True, False, False]]


def test_goal_ward_leaves_the_escape_s_wall_following_alone() -> None:
    inner = Recording([])
    escaping = replace(_obs(goal_xy=GOAL_LEFT), behaviour="wall-left")
    GoalWard(inner, ROBOT, "goal").decide(escaping)
    assert inner.preferences == [None]


def test_tie_passes_the_side_of_the_last_turn() -> None:
    right_arc = Decision(Command(0.3, -0.3), trajectory=5, choice=5)  # T1R
    left_spin = Decision(Command.spin(1.0))
    inner = Recording([right_arc, left_spin, right_arc])
    reflex = TieToLastTurn(inner, ROBOT, "avoid")
    for _ in range(3):
        reflex.decide(_obs())
    assert inner.tie_sides == [1, -1, 1]


def test_the_paper_policy_alone_has_no_tie_side() -> None:
    inner = Recording([Decision(Command(0.3, -0.3), trajectory=5, choice=5)] * 2)
    wrapped = wrap(inner, (), ROBOT, "avoid")
    wrapped.decide(_obs())
    wrapped.decide(_obs())
    assert inner.tie_sides == [0, 0]


@pytest.mark.parametrize(("behaviour", "away"), [("wall-left", -1), ("wall-right", 1)])
def test_wall_start_turns_ties_away_from_the_wall_side_until_the_wall_is_found(
    behaviour: str, away: int
) -> None:
    searching = Decision(Command(0.6, 0.0), trajectory=3, choice=3)
    found = Decision(Command(0.6, 0.0), trajectory=3, choice=3, following_wall=True)
    inner = Recording([searching, found, found])
    reflex = WallStart(inner, ROBOT, behaviour)
    for _ in range(3):
        reflex.decide(_obs())
    assert inner.tie_sides == [away, away, 0]


def test_wall_start_leaves_other_behaviours_alone() -> None:
    inner = Recording([Decision(Command(0.6, 0.0))])
    WallStart(inner, ROBOT, "avoid").decide(_obs())
    assert inner.tie_sides == [0]


def test_reflexes_stack_in_one_order_whatever_order_they_are_named_in() -> None:
    assert parse_reflexes("tie,bump,blocked-ways") == ("blocked-ways", "bump", "tie")
    assert parse_reflexes("all") == STACK_ORDER
    assert parse_reflexes("none") == ()


def test_the_registry_holds_every_reflex_a_method_can_name_in_its_stacking_order() -> None:
    assert tuple(REFLEXES) == REFLEX_NAMES == STACK_ORDER
    assert all(reflex.name == name for name, reflex in REFLEXES.items())


def test_an_unknown_reflex_is_bad_input() -> None:
    with pytest.raises(BadInput, match="unknown reflex bumpy"):
        parse_reflexes("bump,bumpy")
