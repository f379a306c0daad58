"""The paper's TVL choice rule as a policy (§2.1–2.2, §4.5): perceive the seven trajectory
velocities, take the fast one that best fits the behaviour, rotating perception round the
ring when none is fast ahead, and drive it at its perceived velocity. Nothing else: every
addition is a reflex (agent.reflexes)."""

from __future__ import annotations

from typing import Protocol

import numpy as np

from tvl_cli.agent.motions import spin_commands
from tvl_cli.agent.perception import Perception
from tvl_cli.agent.policy import Decision, Observation
from tvl_cli.core.angles import goal_bearing
from tvl_cli.core.drive_command import Command
from tvl_cli.core.learn_params import BACKOFF_M
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.trajectory_choice import (
    Choice,
    Context,
    choose,
    fast_set,
    trajectory_headings,
)
from tvl_cli.core.wall_rules import FIRST_SEEN, WALL_RULES

# Trapped (nothing fast in any direction): turn slowly on the spot so the ring sees anew.
TRAPPED_SPIN_RADPS = 0.3
# How far trajectories are judged where they set off, for advice that leaves ways out: the
# stretch in which an obstacle just met lies, which is the distance the robot backs off.
SET_OFF_M = BACKOFF_M


class VelocityPerception(Protocol):
    """What the choice perceives the trajectories' velocities by: a FAM (core.fam.Fam), or
    a reference that reads the map (agent.true_velocities)."""

    def perceive(self, ring_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(16, 7) m/s of each trajectory in each view (row k facing sonar k), and their
        experience."""
        ...

    def perceive_ahead(self, ring_m: np.ndarray) -> np.ndarray:
        """(7,) m/s: row 0 of `perceive`, the view the robot faces, alone."""
        ...


class TvlPolicy:
    """Drives one behaviour from a FAM's perception."""

    def __init__(
        self,
        fam: VelocityPerception,
        robot: RobotConfig,
        behaviour: str,
        threshold: float,
        perception: Perception | None = None,
        wall_rule: str = FIRST_SEEN,
    ) -> None:
        self.fam = fam
        # Everything the choice reads of the ring, the FAM and the behaviours' rules alike,
        # is what perception makes of it: the live ring, or the echo memory's virtual ring.
        self.perception = perception or Perception(NO_MEMORY, robot)
        self.robot = robot
        self.behaviour = behaviour
        self.threshold = threshold
        self._v_max = np.array(robot.v_max_mps)
        curvatures = np.array([t.curvature_per_m for t in robot.trajectories])
        self._headings = trajectory_headings(curvatures, robot.sonar.count)
        self._set_off = trajectory_headings(curvatures, robot.sonar.count, SET_OFF_M)
        self._queue: list[Decision] = []  # the rest of a plan: spin steps, then the trajectory
        # How wall following finds its wall, where the paper is silent (core.wall_rules).
        self._wall_rule = WALL_RULES[wall_rule]
        self._wall_side = 0
        self._performing = behaviour  # the behaviour of the last choice, advice included
        self._trapped = False

    def interrupt(self) -> None:
        self._queue = []

    def decide(self, obs: Observation) -> Decision:
        if self._queue:
            return self._queue.pop(0)
        ring_m = self.perception.sense(obs.time_s, obs.odometry, obs.ring_m, obs.goal_xy)
        perceived = ring_m if self.perception.remembers else None
        behaviour = obs.behaviour or self.behaviour
        if behaviour != self._performing:
            # A wall found for one behaviour is not the next one's: it finds its own.
            self._performing, self._wall_side = behaviour, 0
        self._wall_side = self._wall_rule(behaviour, ring_m, self._wall_side)
        velocities, fast = self._perceived(ring_m, obs)
        # A reflex's preferred ways, by where they head as the behaviours judge them; the
        # record keeps the whole fast set.
        candidates = fast
        if obs.prefer is not None:
            preferred = fast & obs.prefer(self._headings)
            if preferred.any():
                candidates = preferred
        bearing = 0.0 if obs.goal_xy is None else goal_bearing(obs.odometry, obs.goal_xy)
        ctx = Context(ring_m, obs.tie_side, bearing, self._wall_side)
        choice = choose(velocities, candidates, self._v_max, self._headings, behaviour, ctx)
        following = self._wall_side != 0
        if choice is None:
            became_trapped = not self._trapped
            self._trapped = True
            spin = Command.spin(TRAPPED_SPIN_RADPS * (-1 if obs.tie_side < 0 else 1))
            return Decision(
                spin,
                velocities=velocities[0],
                fast=fast[0],
                trapped=became_trapped,
                following_wall=following,
                perceived_m=perceived,
            )
        self._trapped = False
        return self._plan(choice, velocities, fast, following, perceived)

    def _perceived(self, ring_m: np.ndarray, obs: Observation) -> tuple[np.ndarray, np.ndarray]:
        """(V, 7) m/s and their fast set: the view ahead alone (V = 1) where it has a fast way,
        else all sixteen, row k facing sonar k.

        The rule looks round the ring only when no way ahead is fast (core.trajectory_choice),
        so a step that drives on perceives one view of sixteen and chooses as if it had
        perceived them all; a reflex's preference must know every view from the start."""
        if obs.prefer is None:
            ahead = self.fam.perceive_ahead(ring_m)[None]  # (1, 7) m/s
            fast = self._fast(ahead, obs)
            if fast[0].any():
                return ahead, fast
        velocities, _ = self.fam.perceive(ring_m)  # (16, 7) m/s
        return velocities, self._fast(velocities, obs)

    def _fast(self, velocities: np.ndarray, obs: Observation) -> np.ndarray:
        """(V, 7) bool: the fast ways of the first V views, less those a reflex keeps out."""
        fast = fast_set(velocities, self._v_max, self.threshold)
        if obs.keep_out is not None:
            fast &= ~obs.keep_out(self._set_off[: len(velocities)])
        return fast

    def _plan(
        self,
        choice: Choice,
        velocities: np.ndarray,
        fast: np.ndarray,
        following: bool,
        perceived: np.ndarray | None,
    ) -> Decision:
        """Spin to face the chosen view, then follow the trajectory: one decision a step."""
        row = choice.rotation % len(velocities)
        record = Decision(
            Command.follow(self.robot.trajectories[choice.trajectory], choice.speed_mps),
            trajectory=choice.trajectory,
            choice=choice.trajectory,
            rotation=choice.rotation,
            velocities=velocities[row],
            fast=fast[row],
            following_wall=following,
            perceived_m=perceived,
        )
        spins = [
            Decision(c, following_wall=following)
            for c in spin_commands(choice.rotation, self.robot)
        ]
        if not spins:
            return record
        # The first spin step carries the record of the choice; the trajectory follows them.
        first = Decision(
            spins[0].command,
            choice=choice.trajectory,
            rotation=choice.rotation,
            velocities=record.velocities,
            fast=record.fast,
            following_wall=following,
            perceived_m=perceived,
        )
        self._queue = [*spins[1:], record]
        return first
