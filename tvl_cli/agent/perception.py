"""What the FAM reads: the live ring, or the virtual ring of the echo memory (core.memory).

The memory is fed the readings the robot perceives with, each at the odometry pose and the
control step it was read at, and answers for any later pose. It knows nothing of the true
pose or the map. Steps are counted, not timed, so that replaying a log's exemplars rebuilds
exactly the virtual rings a learner perceived.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from tvl_cli.agent.policy import Pose
from tvl_cli.core.angles import goal_bearing
from tvl_cli.core.episode import Episode
from tvl_cli.core.memory import CLEARED_ABOVE_M, GOAL_BEAMS_EITHER_SIDE, POINTS, MemoryConfig
from tvl_cli.core.ring import mm_to_ring
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.training import SessionEpisodes
from tvl_cli.sim.sonar import SonarRing


class EchoMemory:
    """The echoes of the last `config.window_s`, in the odometry frame; with `clears`, a beam
    that hears an echo meets only the patches narrow enough, and with `opens_toward_goal` the
    beams facing the goal none (core.memory, *clearing*)."""

    def __init__(
        self,
        config: MemoryConfig,
        robot: RobotConfig,
        clears: bool = False,
        opens_toward_goal: bool = False,
    ) -> None:
        # The compiled kernels are loaded with the first memory, so that a command's help, or
        # a run without a memory, never loads the compiler.
        from tvl_cli.agent.memory_kernel import remember_echoes, remembered_ranges

        self._keep = remember_echoes
        self._cast = remembered_ranges
        self.config = config
        self.clears = clears
        self.opens_toward_goal = opens_toward_goal
        sonar = robot.sonar
        self._sonar = sonar
        self._ring = SonarRing(sonar, robot.radius_m)
        self._window_steps = max(1, round(config.window_s / robot.control_period_s))
        capacity = self._window_steps * sonar.count
        self._centres = np.zeros((capacity, 2))  # (C, 2) echo points, metres
        self._axes = np.zeros((capacity, 2))  # (C, 2) unit beam axes they were heard along
        self._half_widths = np.zeros(capacity)  # (C,) metres
        self._steps = np.full(capacity, -(2**62), dtype=np.int64)  # (C,) step heard; old
        self._next = 0
        self._half_cone = math.radians(sonar.cone_deg) / 2.0
        self._tan_half_cone = math.tan(self._half_cone)
        self._rays = sonar.rays_per_beam

    @property
    def window_steps(self) -> int:
        """How many control steps of echoes it keeps."""
        return self._window_steps

    def remember(self, step: int, odometry: Pose, ring_m: np.ndarray) -> None:
        """Keep the echoes of a reading taken at `odometry` on control step `step`."""
        self._remember(step, *self._ring.rays(odometry), ring_m)

    def _remember(
        self, step: int, origins: np.ndarray, directions: np.ndarray, ring_m: np.ndarray
    ) -> None:
        self._next = self._keep(
            origins,
            directions,
            self._rays,
            ring_m,
            self._sonar.max_range_m,
            self.config.range_m,
            self._tan_half_cone,
            self.config.patch_m / 2.0,
            step,
            self._centres,
            self._axes,
            self._half_widths,
            self._steps,
            self._next,
        )

    def virtual(
        self, step: int, odometry: Pose, ring_m: np.ndarray, goal_rad: float | None = None
    ) -> np.ndarray:
        """(16,) metres: each sonar's live range or the nearest remembered surface in its
        cone from `odometry`, whichever is nearer; `goal_rad` is the goal's bearing from the
        heading, if one is sought."""
        return self._virtual(step, *self._ring.rays(odometry), ring_m, goal_rad)

    def _cleared_above_m(self, ring_m: np.ndarray, goal_rad: float | None) -> np.ndarray:
        """(16,) metres: how wide a patch each beam still meets, either side (inf: every one)."""
        heard = ring_m < self._sonar.max_range_m
        limits = np.full(len(ring_m), np.inf)
        if self.clears:
            limits[heard] = CLEARED_ABOVE_M
        if self.opens_toward_goal and goal_rad is not None:
            beams = len(ring_m)
            nearest = round(goal_rad / (2.0 * math.pi / beams))
            for k in range(-GOAL_BEAMS_EITHER_SIDE, GOAL_BEAMS_EITHER_SIDE + 1):
                beam = (nearest + k) % beams
                if heard[beam]:
                    limits[beam] = 0.0  # every patch is wider than none
        return limits

    def _virtual(
        self,
        step: int,
        origins: np.ndarray,
        directions: np.ndarray,
        ring_m: np.ndarray,
        goal_rad: float | None = None,
    ) -> np.ndarray:
        sonar = self._sonar
        remembered = self._cast(
            self.config.kind,
            origins,
            directions,
            self._rays,
            self._half_cone,
            self._centres,
            self._axes,
            self._half_widths,
            self._steps,
            step - self._window_steps + 1,
            ring_m,  # a surface no nearer than the live reading changes nothing below
            self._cleared_above_m(ring_m, goal_rad),
        )
        return np.minimum(ring_m, np.clip(remembered, sonar.min_range_m, sonar.max_range_m))

    def surfaces(
        self, step: int, near_xy: tuple[float, float], within_m: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """What is remembered on control step `step` within `within_m` of `near_xy`, in the
        odometry frame: patches as segments (n, 4) x1, y1, x2, y2, and points as discs of no
        radius (m, 3), metres."""
        reach = within_m + self._half_widths  # (C,) a patch's end may be nearer its centre
        gap = np.hypot(self._centres[:, 0] - near_xy[0], self._centres[:, 1] - near_xy[1])
        live = (self._steps > step - self._window_steps) & (gap <= reach)
        centres, axes = self._centres[live], self._axes[live]
        if self.config.kind == POINTS:
            return np.empty((0, 4)), np.column_stack([centres, np.zeros(len(centres))])
        across = np.stack([-axes[:, 1], axes[:, 0]], axis=1) * self._half_widths[live, None]
        return np.hstack([centres - across, centres + across]), np.empty((0, 3))

    def sense(
        self, step: int, odometry: Pose, ring_m: np.ndarray, goal_rad: float | None = None
    ) -> np.ndarray:
        """Remember a reading, then the virtual ring it makes."""
        rays = self._ring.rays(odometry)  # the same beams for both, cast once a step
        self._remember(step, *rays, ring_m)
        return self._virtual(step, *rays, ring_m, goal_rad)


class Perception:
    """The stage between the ring and the FAM: the live ring itself without a memory. The
    memory clears as its `clearing` says for a robot `seeking_goal` or not."""

    def __init__(
        self, config: MemoryConfig, robot: RobotConfig, seeking_goal: bool = False
    ) -> None:
        self.config = config
        self._dt_s = robot.control_period_s
        self._memory = (
            EchoMemory(
                config,
                robot,
                config.clears(seeking_goal),
                config.opens_toward_goal(seeking_goal),
            )
            if config.remembers
            else None
        )

    @property
    def remembers(self) -> bool:
        return self._memory is not None

    def step_of(self, time_s: float) -> int:
        return round(time_s / self._dt_s)

    def sense(
        self,
        time_s: float,
        odometry: Pose,
        ring_m: np.ndarray,
        goal_xy: tuple[float, float] | None = None,
    ) -> np.ndarray:
        """(16,) metres the FAM reads, remembering this reading; `goal_xy` is the goal of a
        robot seeking one, in the odometry frame."""
        if self._memory is None:
            return ring_m
        goal_rad = None  # read only by a memory that opens toward the goal
        if goal_xy is not None and self._memory.opens_toward_goal:
            goal_rad = goal_bearing(odometry, goal_xy)
        return self._memory.sense(self.step_of(time_s), odometry, ring_m, goal_rad)

    def peek(self, time_s: float, odometry: Pose, ring_m: np.ndarray) -> np.ndarray:
        """(16,) metres the FAM reads, without remembering this reading (an explorer's look,
        with no goal)."""
        if self._memory is None:
            return ring_m
        return self._memory.virtual(self.step_of(time_s), odometry, ring_m)


def replayed_rings(
    config: MemoryConfig,
    robot: RobotConfig,
    steps: Sequence[int] | np.ndarray,
    odometry: np.ndarray,
    rings_m: np.ndarray,
) -> np.ndarray:
    """(N, 16) metres: the virtual rings of readings (N, 16) taken in order at `odometry`
    (N, 3) on control `steps` (N,), each remembered before its own is made, as a learner
    (who seeks no goal) perceived them."""
    if not config.remembers:
        return rings_m
    memory = EchoMemory(config, robot, config.clears(seeking_goal=False))
    virtual = np.empty_like(rings_m)
    for i, (step, pose, ring) in enumerate(zip(steps, odometry, rings_m, strict=True)):
        virtual[i] = memory.sense(int(step), (pose[0], pose[1], pose[2]), ring)
    return virtual


def perceived_episodes(
    episodes: Sequence[Episode], memory: MemoryConfig, robot: RobotConfig
) -> list[Episode]:
    """A session's episodes, in order from its first, with what the FAM reads at each
    exemplar through `memory`: the exemplars' readings replayed into the memory in order, as a
    learner perceived them. Given only the episodes up to some time, the memory is replayed no
    further, since what it held later cannot change what it read before."""
    if not memory.remembers or not episodes:
        return list(episodes)
    virtual = replayed_rings(
        memory,
        robot,
        np.concatenate([e.steps(robot.control_period_s) for e in episodes]),
        np.concatenate([e.odometry for e in episodes]),
        mm_to_ring(np.concatenate([e.ring_mm for e in episodes])),
    )
    starts = np.cumsum([0] + [e.exemplar_count for e in episodes])
    return [
        replace(episode, fam_ring_m=virtual[start : start + episode.exemplar_count])
        for episode, start in zip(episodes, starts, strict=False)
    ]


def perceived_session(
    learnt: SessionEpisodes, memory: MemoryConfig, robot: RobotConfig
) -> SessionEpisodes:
    """A session's episodes to train on, each with what the FAM reads through `memory` at its
    exemplars (perceived_episodes)."""
    return replace(learnt, episodes=perceived_episodes(learnt.episodes, memory, robot))
