"""Every rule beyond the paper around the choice rule, each a named wrapper around any policy
and an entry of core.additions.ADDITIONS.

A reflex sees each observation before the policy it wraps. It may pass the policy advice
(ways to keep out of the choice, the side a tie goes to) and may take over the command
itself for a while (backing off). A method's `reflexes` (`--reflex NAME[,NAME...]`) picks
them; the paper's method has none. Whatever the order they are named in, they stack in
STACK_ORDER, outermost first.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from tvl_cli.agent.motions import backoff_commands
from tvl_cli.agent.policy import Decision, Observation, Policy, WayMask
from tvl_cli.core.angles import goal_bearing, wrap_rad
from tvl_cli.core.contacts import blind_ahead, drives_forward, near_miss_sonars
from tvl_cli.core.drive_command import Command
from tvl_cli.core.learn_params import BACKOFF_M
from tvl_cli.core.method import (
    BLOCKED_WAYS,
    BUMP,
    ESCAPE,
    GOAL_WARD,
    NEAR_MISS,
    REFLEX_NAMES,
    TIE,
    WALL_START,
)
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.trajectory_choice import trajectory_headings

# How long a way that met an obstacle stays out of the choice once backed off: time to drive
# clear of the spot, short enough to try that way again later.
BLOCKED_S = 2.0
# Trajectories setting off within this angle of a way that met an obstacle are left out:
# more than two sonar spacings, so that facing the next sonar but one (exactly 45 degrees
# round) is never decided by the noise in odometry.
BLOCKED_HALF_WIDTH_RAD = math.radians(50.0)


class Reflex:
    """A policy wrapped: by default it passes everything through."""

    name = ""

    def __init__(self, inner: Policy, robot: RobotConfig, behaviour: str) -> None:
        self.inner = inner
        self.robot = robot
        self.behaviour = behaviour

    def decide(self, obs: Observation) -> Decision:
        return self.inner.decide(obs)

    def interrupt(self) -> None:
        self.inner.interrupt()


class _BackOff(Reflex):
    """Reverses BACKOFF_M along the arc the robot was driving when `triggered` says so, then
    hands back to the policy it wraps, which starts afresh."""

    def __init__(self, inner: Policy, robot: RobotConfig, behaviour: str) -> None:
        super().__init__(inner, robot, behaviour)
        self._queue: list[Command] = []
        self._last: Command | None = None  # the last command this reflex let through

    def triggered(self, obs: Observation) -> bool:
        raise NotImplementedError

    def decide(self, obs: Observation) -> Decision:
        if not self._queue and drives_forward(self._last) and self.triggered(obs):
            assert self._last is not None
            self._queue = backoff_commands(self._last, self.robot, BACKOFF_M)
            self.inner.interrupt()
        if self._queue:
            self._last = self._queue.pop(0)
            return Decision(self._last, reflex=self.name)
        decision = self.inner.decide(obs)
        self._last = decision.command
        return decision

    def interrupt(self) -> None:
        self._queue, self._last = [], None
        super().interrupt()


class NearMissBackOff(_BackOff):
    """An object in the blind zone ahead while driving forward: back off as after a bump.

    The ring cannot range an object inside its 0.15 m minimum, so it cannot tell how close
    it is; backing off avoids the touch. (Learning's `--near` places a collision point there
    for the same reason.)
    """

    name = NEAR_MISS

    def __init__(self, inner: Policy, robot: RobotConfig, behaviour: str) -> None:
        super().__init__(inner, robot, behaviour)
        self._sonars = near_miss_sonars(robot.sonar.count)

    def triggered(self, obs: Observation) -> bool:
        return blind_ahead(obs.ring_m, self._sonars, self.robot.sonar.min_range_m)


class BumpBackOff(_BackOff):
    """A bump while driving forward: reverse along the arc, as learning does after one.

    Without it a policy that still rates the way ahead fast pushes on into the obstacle.
    """

    name = BUMP

    def triggered(self, obs: Observation) -> bool:
        return obs.bumped


@dataclass(frozen=True, slots=True)
class BlockedWay:
    """The world heading (by odometry) the robot drove when it met an obstacle, kept out
    of its choices until a time."""

    heading_rad: float
    until_s: float


def keep_out_ways(bearings_rad: list[float]) -> WayMask:
    """Advice leaving out every trajectory that sets off within BLOCKED_HALF_WIDTH_RAD of
    one of the bearings (radians, relative to the heading)."""
    bearings = np.array(bearings_rad)

    def blocked(set_off_rad: np.ndarray) -> np.ndarray:
        gaps = np.abs(wrap_rad(set_off_rad[..., None] - bearings))
        return np.asarray((gaps <= BLOCKED_HALF_WIDTH_RAD).any(axis=-1))

    return blocked


class BlockedWays(Reflex):
    """After a bump or a near miss, the way the robot was driving stays out of every choice
    until BLOCKED_S after any back-off ends: every trajectory setting off within
    BLOCKED_HALF_WIDTH_RAD of it, in every rotated view. Several can hold at once.

    A contact is evidence the policy over-rated that way: after backing off the ring reads
    much the same, and an object it cannot see (a convex corner, a table edge) is still
    there, so trusting it again would meet it again.
    """

    name = BLOCKED_WAYS

    def __init__(self, inner: Policy, robot: RobotConfig, behaviour: str) -> None:
        super().__init__(inner, robot, behaviour)
        self._sonars = near_miss_sonars(robot.sonar.count)
        self._ways: list[BlockedWay] = []
        self._last: Command | None = None
        self._was_bumped = False

    @property
    def blocked_ways(self) -> tuple[BlockedWay, ...]:
        """The ways kept out of the choice, as of the last step."""
        return tuple(self._ways)

    def _met_obstacle(self, obs: Observation) -> bool:
        if not drives_forward(self._last):
            return False
        bumped = obs.bumped and not self._was_bumped
        return bumped or blind_ahead(obs.ring_m, self._sonars, self.robot.sonar.min_range_m)

    def decide(self, obs: Observation) -> Decision:
        now = obs.time_s
        if self._met_obstacle(obs):
            self._ways.append(BlockedWay(obs.odometry[2], now + BLOCKED_S))
        self._was_bumped = obs.bumped
        self._ways = [w for w in self._ways if now < w.until_s]
        if self._ways:
            bearings = [wrap_rad(w.heading_rad - obs.odometry[2]) for w in self._ways]
            obs = replace(obs, keep_out=keep_out_ways(bearings))
        decision = self.inner.decide(obs)
        if decision.command.linear_mps < 0.0 and self._ways:
            # Timed from the end of the back-off: the way stays blocked while reversing.
            latest = self._ways[-1]
            until = now + self.robot.control_period_s + BLOCKED_S
            self._ways[-1] = BlockedWay(latest.heading_rad, max(latest.until_s, until))
        self._last = decision.command
        return decision

    def interrupt(self) -> None:
        self._last = None
        super().interrupt()


# Goal seeking that has come no nearer its goal for this long is caught in a local minimum:
# a pillar in the way is passed well within it, a crevice or a closed gap never is.
STALLED_S = 20.0
# Progress is coming this much nearer the goal than ever before, by odometry: more than a
# turn on the spot or a back-off moves the robot.
PROGRESS_M = 0.25
# The first escape follows a wall this long; each next, on the other side, twice as long.
FIRST_ESCAPE_S = 15.0
ESCAPE_SIDES = ("wall-left", "wall-right")


class WallEscape(Reflex):
    """Goal seeking that has come no nearer the goal for STALLED_S follows walls for a
    while instead: the wall on the left for FIRST_ESCAPE_S, the next time on the right for
    twice as long, and so on, each escape ending as soon as the robot is PROGRESS_M nearer
    the goal than it has ever been.

    The paper's way out of a deep local minimum (§2.1, Fig. 5(b)): following fast
    trajectories towards the goal cannot leave a crevice that faces it, or a gap the ring
    cannot resolve, while following walls both ways for longer and longer leads round them.
    Distances are by odometry, as the goal's bearing is.
    """

    name = ESCAPE

    def __init__(self, inner: Policy, robot: RobotConfig, behaviour: str) -> None:
        super().__init__(inner, robot, behaviour)
        self._closest_m = math.inf  # the nearest the robot has come to the goal
        self._progress_s = 0.0  # when it last came PROGRESS_M nearer than before
        self._escapes = 0
        self._escape_until_s = -math.inf

    def decide(self, obs: Observation) -> Decision:
        if self.behaviour != "goal" or obs.goal_xy is None:
            return self.inner.decide(obs)
        now = obs.time_s
        distance = math.dist(obs.odometry[:2], obs.goal_xy)
        if distance <= self._closest_m - PROGRESS_M:
            self._closest_m, self._progress_s = distance, now
            self._escape_until_s = min(self._escape_until_s, now)
        if now >= self._escape_until_s and now - self._progress_s >= STALLED_S:
            self._escape_until_s = now + FIRST_ESCAPE_S * 2**self._escapes
            self._escapes += 1
            # Goal seeking begins afresh when the escape ends, its STALLED_S counted anew.
            self._progress_s = self._escape_until_s
        if now < self._escape_until_s:
            obs = replace(obs, behaviour=ESCAPE_SIDES[(self._escapes - 1) % 2])
        return self.inner.decide(obs)


# A way heads toward the goal when, half a metre along it (the choice rule's look-ahead), it
# points within this angle of the goal's bearing: it does not turn the robot's back on it.
GOAL_WARD_HALF_WIDTH_RAD = math.radians(90.0)


class GoalWard(Reflex):
    """While seeking a goal, the choice is among the fast ways heading toward the goal
    whenever any view has one: where the fast way ahead that best fits the goal would turn
    the robot's back on it, the robot turns to face the nearest view that has a fast way
    toward the goal instead.

    The paper rotates its perception only when nothing is fast ahead (§4.5). Where the way
    toward the goal through a gap reads just under the threshold ahead, it takes a fast way
    that leads off to one side, then keeps taking what is fast in the view it turned to: the
    goal ends up behind it and it wanders back into the open (the single FAM among Figure
    22's pillars). Turned to face the gap, the ring reads it anew.
    """

    name = GOAL_WARD

    def decide(self, obs: Observation) -> Decision:
        # Inside the escape: while it follows walls, the observation's behaviour says so.
        behaviour = obs.behaviour or self.behaviour
        if behaviour != "goal" or obs.goal_xy is None:
            return self.inner.decide(obs)
        bearing = goal_bearing(obs.odometry, obs.goal_xy)

        def toward_goal(headings: np.ndarray) -> np.ndarray:
            return np.abs(wrap_rad(headings - bearing)) <= GOAL_WARD_HALF_WIDTH_RAD

        return self.inner.decide(replace(obs, prefer=toward_goal))


class TieToLastTurn(Reflex):
    """Ties go to the side the robot last turned to, spin and arc together.

    Without it a tie goes to the policy's own first choice (the left), and a robot that
    has just turned right away from a wall can turn straight back towards it.
    """

    name = TIE

    def __init__(self, inner: Policy, robot: RobotConfig, behaviour: str) -> None:
        super().__init__(inner, robot, behaviour)
        curvatures = np.array([t.curvature_per_m for t in robot.trajectories])
        self._sides = np.sign(trajectory_headings(curvatures, robot.sonar.count)).astype(int)
        self._side = 1

    def decide(self, obs: Observation) -> Decision:
        decision = self.inner.decide(replace(obs, tie_side=self._side))
        side = self._turn_side(decision)
        if side:
            self._side = side
        return decision

    def _turn_side(self, decision: Decision) -> int:
        if decision.choice >= 0:
            return int(self._sides[decision.rotation % len(self._sides), decision.choice])
        command = decision.command
        return int(np.sign(command.angular_radps)) if command.linear_mps >= 0.0 else 0


class WallStart(Reflex):
    """Until wall following has found its wall, ties turn away from that side, so that the
    first wall met ahead is left on the side to follow rather than on the other."""

    name = WALL_START

    def __init__(self, inner: Policy, robot: RobotConfig, behaviour: str) -> None:
        super().__init__(inner, robot, behaviour)
        self._side = {"wall-left": 1, "wall-right": -1}.get(behaviour, 0)
        self._found = False

    def decide(self, obs: Observation) -> Decision:
        if self._side and not self._found:
            obs = replace(obs, tie_side=-self._side)
        decision = self.inner.decide(obs)
        self._found = self._found or decision.following_wall
        return decision


# Outermost first: blocked ways see every command, back-offs included; the escape, the goal-
# ward choice (inside the escape, so that it leaves the escape's wall following alone), ties
# and the wall start advise the policy directly.
REFLEXES: dict[str, type[Reflex]] = {
    r.name: r
    for r in (
        BlockedWays,
        NearMissBackOff,
        BumpBackOff,
        WallEscape,
        GoalWard,
        TieToLastTurn,
        WallStart,
    )
}
STACK_ORDER = REFLEX_NAMES


def wrap(policy: Policy, names: tuple[str, ...], robot: RobotConfig, behaviour: str) -> Policy:
    """The policy inside the named reflexes, stacked in STACK_ORDER."""
    for name in reversed(STACK_ORDER):
        if name in names:
            policy = REFLEXES[name](policy, robot, behaviour)
    return policy
