"""What drives the robot: a policy maps an observation to a command and a decision record.

The paper's TVL choice rule is one policy (`agent.tvl`); the baselines are others. Reflexes
(`agent.reflexes`) wrap any policy: they may pass it advice in the observation (ways to keep
out of the choice, the side a tie goes to, a behaviour to perform for a while) and may
override the command it returns.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Protocol

import numpy as np

from tvl_cli.core.drive_command import Command

Pose = tuple[float, float, float]  # x, y metres; heading radians, CCW from +x


# Headings of trajectories (radians, relative to the heading now, any shape) -> a bool mask
# of those the advice names: ways to leave out of the choice, or ways to prefer in it.
WayMask = Callable[[np.ndarray], np.ndarray]


class LazyRing:
    """One step's sonar reading, taken on first use and shared by every view of the step.

    Steps where nothing looks at the ring (a spin or a back-off under way) draw no sonar
    noise: a run's random stream then depends on what its policy reads, never on whether
    it is being traced.
    """

    __slots__ = ("_read", "value")

    def __init__(self, read: Callable[[], np.ndarray]) -> None:
        self._read = read
        self.value: np.ndarray | None = None

    def get(self) -> np.ndarray:
        if self.value is None:
            self.value = self._read()
        return self.value


@dataclass(frozen=True, slots=True)
class Observation:
    """What the robot knows before a control step, and the advice reflexes add to it."""

    time_s: float
    ring: LazyRing
    odometry: Pose
    bumped: bool  # the bump sensor after the last step
    goal_xy: tuple[float, float] | None = None
    # Advice from reflexes; a policy that cannot use it ignores it.
    # which ways to leave out of the choice, by where they set off
    keep_out: WayMask | None = None
    # which ways to choose among whenever one of them is fast, by where they head (the
    # choice rule's look-ahead); the others only when none is
    prefer: WayMask | None = None
    tie_side: int = 0  # +1 left, -1 right: where a tie goes; 0 the policy's own order
    behaviour: str = ""  # a behaviour to perform instead of the policy's own; "" its own

    @property
    def ring_m(self) -> np.ndarray:
        """(16,) metres, S0 forward, CCW."""
        return self.ring.get()


@dataclass(frozen=True, slots=True)
class Decision:
    """A command and why: the record a run trace keeps of every step."""

    command: Command
    trajectory: int = -1  # trajectory followed this step; -1 spinning, reversing or stopped
    choice: int = -1  # the trajectory the policy chose, before any reflex; -1 none
    rotation: int = 0  # the view the choice was made in, sonar positions CCW
    velocities: np.ndarray | None = None  # (7,) m/s perceived in that view; None: no view
    fast: np.ndarray | None = None  # (7,) bool: the fast set of that view
    reflex: str = ""  # the reflex that overrode the policy, if one did
    trapped: bool = False  # the policy found nothing fast in any direction
    following_wall: bool = False  # a wall to follow has been found (wall clearance counts)
    # (16,) metres the choice read of the ring when it was not the live ring itself: the echo
    # memory's virtual ring; None otherwise.
    perceived_m: np.ndarray | None = None

    def overridden(self, reflex: str, command: Command) -> Decision:
        """This decision with its command replaced by a reflex's."""
        return replace(self, command=command, trajectory=-1, reflex=reflex)


class Policy(Protocol):
    def decide(self, obs: Observation) -> Decision:
        """The command for the next control period, and why."""
        ...

    def interrupt(self) -> None:
        """A reflex has taken over: drop any plan under way (a spin, a queued turn)."""
        ...
