"""Collision points heard: every recorded point labels all seven trajectories from the echoes
the ring heard around it, placed by odometry (paper §2: collision points "obtained by using
accumulated sensor data and odometry"), where the paper's learner labels only the trajectory
it drove, from the bump that ended it.

An echo is placed where the reading's transducer faced, at its range from the body's edge:
a point on the transducer's axis in the odometry frame. Each recorded point's collision
point on a trajectory is where the body, driven along it from the odometry pose of that
point, would first come within the sonar's minimum range (core.arcs.collision_clearance_m)
of one of the echoes read from `window_s` before the point to `window_s` after it: the
readings of every episode of the session in that time, the echoes of walls the ring heard
square on only from elsewhere among them. The driven trajectory keeps the collision point
its episode found (a bump, a sonar's collision point, or none after a full circle), which
it met rather than heard. A stretch driven while behaving (agent.online) met its collision
point only at a bump or a near point, and estimated it otherwise, from a few seconds of
echoes: its driven trajectory takes the nearer of that point and the heard one.

The evidence supports a label when the point's window was heard whole after it: the
session went on for `window_s` after the point. A point nearer the session's end labels its
driven trajectory alone. A trajectory that meets no echo within the window is free, where
its label stops changing (a wall that stays silent for the whole of a 10-second window
around a point is rare: benchmarks/label_accuracy.py measures how rare, and how far heard
labels are from those of the true map).

Nothing here reads the true pose or the map: the episodes' odometry and rings alone.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from tvl_cli.core.arcs import collision_clearance_m
from tvl_cli.core.episode import Episode
from tvl_cli.core.ring import mm_to_ring
from tvl_cli.core.robot_config import RobotConfig

# Before and after each point: long enough that a wall met at a slant, silent from the
# point, is heard square on from somewhere in the window; short enough that odometry's drift
# and the echoes placed off their objects (a cone's reading is put on its axis) stay few.
# Chosen on the tuning worlds (benchmarks/label_accuracy.py, docs/method.md).
DEFAULT_WINDOW_S = 10.0


def echo_points(odometry: np.ndarray, ring_m: np.ndarray, robot: RobotConfig) -> np.ndarray:
    """(N, sonars, 2) metres: where each reading (N, sonars) taken at `odometry` (N, 3) places
    its echo, on its transducer's axis at its range from the body's edge; NaN where it heard
    nothing (the maximum range)."""
    count = robot.sonar.count
    angle = odometry[:, 2:3] + np.arange(count) * (2 * math.pi / count)  # (N, sonars) rad
    reach = np.where(ring_m < robot.sonar.max_range_m, robot.radius_m + ring_m, np.nan)
    return np.stack(
        [odometry[:, 0:1] + reach * np.cos(angle), odometry[:, 1:2] + reach * np.sin(angle)],
        axis=-1,
    )


@dataclass(frozen=True, slots=True, eq=False)
class HeardEpisode:
    """An episode and the collision point of every trajectory at each of its exemplars."""

    episode: Episode
    # (n, trajectories) metres along each trajectory from each exemplar: inf where none is
    # heard, NaN where the evidence does not support a label (the driven one is never NaN).
    # A heard one farther than the labeller's reach, where it changes no label, may be
    # farther still or inf.
    distances_m: np.ndarray


class HeardLabeller:
    """Labels one session's episodes, handed in the order they ended, each once the readings
    of its window are all in (`add`), the rest when the session ends (`finish`): a learner
    and `tvl train` replaying its log hand the same episodes in and get the same labels.

    Echoes are sought `reach_m` along each trajectory (core.labels.label_reach_m: nothing
    farther changes a label), or all of them with math.inf."""

    def __init__(
        self,
        robot: RobotConfig,
        reach_m: float,
        window_s: float = DEFAULT_WINDOW_S,
        behaving: bool = False,
    ) -> None:
        self._robot = robot
        # The episodes are stretches driven while behaving, whose own collision points are
        # mostly estimates (the module's docstring).
        self._behaving = behaving
        self._reach_m = reach_m
        self._curvatures = np.array([t.curvature_per_m for t in robot.trajectories])
        self._window = max(1, round(window_s / robot.control_period_s))  # steps
        self._held: deque[Episode] = deque()  # waiting for their window to be heard
        self._steps: list[np.ndarray] = []  # (n,) control steps of the readings kept
        self._points: list[np.ndarray] = []  # (n, sonars, 2) their echoes
        self._last_step = -1  # of the latest reading

    def add(self, episode: Episode) -> list[HeardEpisode]:
        """Take an episode's readings; the episodes whose windows are now whole, labelled."""
        steps = episode.steps(self._robot.control_period_s)
        if len(steps):
            ring = mm_to_ring(episode.ring_mm)
            self._steps.append(steps)
            self._points.append(echo_points(episode.odometry, ring, self._robot))
            self._last_step = int(steps[-1])
        self._held.append(episode)
        ready = []
        while self._held and self._heard_after(self._held[0]):
            ready.append(self._label(self._held.popleft(), supported=True))
        self._forget()
        return ready

    def finish(self) -> list[HeardEpisode]:
        """The session has ended: the episodes still waiting, each labelled where its window
        was heard whole (its driven trajectory at least)."""
        done = [self._label(e, supported=False) for e in self._held]
        self._held.clear()
        return done

    def _heard_after(self, episode: Episode) -> bool:
        """Whether the readings of the window after its last exemplar are all in."""
        if not episode.exemplar_count:
            return True
        last = int(episode.steps(self._robot.control_period_s)[-1])
        return self._last_step >= last + self._window

    def _forget(self) -> None:
        """Drop the readings no held episode's window reaches."""
        if self._held:
            first = self._held[0].steps(self._robot.control_period_s)
            if not len(first):
                return
            oldest = int(first[0]) - self._window
        else:
            oldest = self._last_step - self._window
        while self._steps and int(self._steps[0][-1]) < oldest:
            self._steps.pop(0)
            self._points.pop(0)

    def _label(self, episode: Episode, supported: bool) -> HeardEpisode:
        """Every exemplar's distances: heard on every trajectory where supported (all of the
        episode when `supported`, else those whose window after was heard), and the
        episode's own on the driven one."""
        from tvl_cli.core.contacts_kernel import first_contacts_in_windows  # compiled

        n = episode.exemplar_count
        distances = np.full((n, len(self._curvatures)), np.nan)
        if not n:
            return HeardEpisode(episode, distances)
        steps = episode.steps(self._robot.control_period_s)
        heard = (
            np.arange(n) if supported else np.flatnonzero(steps + self._window <= self._last_step)
        )
        if len(heard) and self._steps:
            # Every echo kept, with the step it was read on: in step order, as read.
            echo_steps = np.repeat(np.concatenate(self._steps), self._robot.sonar.count)
            echoes = np.concatenate(self._points).reshape(-1, 2)
            kept = ~np.isnan(echoes[:, 0])
            echo_steps, echoes = echo_steps[kept], np.ascontiguousarray(echoes[kept])
            first = np.searchsorted(echo_steps, steps[heard] - self._window)
            stop = np.searchsorted(echo_steps, steps[heard] + self._window, side="right")
            found = np.empty((len(heard), len(self._curvatures)))  # (h, T) metres
            first_contacts_in_windows(
                np.ascontiguousarray(episode.odometry[heard]),
                self._curvatures,
                echoes,
                first,
                stop,
                self._robot.radius_m + collision_clearance_m(self._robot),
                self._reach_m,
                False,  # a window's echoes lie in the order they were read
                found,
            )
            distances[heard] = found
        driven = episode.distances_m()  # (n,) metres
        if self._behaving:
            # NaN (unsupported) is no evidence: fmin keeps the stretch's own point there.
            driven = np.fmin(driven, distances[:, episode.trajectory])
        distances[:, episode.trajectory] = driven
        return HeardEpisode(episode, distances)


def heard_episodes(
    episodes: Sequence[Episode],
    robot: RobotConfig,
    ended: bool,
    reach_m: float,
    window_s: float = DEFAULT_WINDOW_S,
    behaving: bool = False,
) -> list[HeardEpisode]:
    """A session's episodes (in order, from its first) labelled as a learner labelled them:
    those whose window was heard whole, and with `ended` (the session's last episode among
    them) the rest as its end labelled them; echoes sought `reach_m` along, the episodes
    stretches driven while behaving if `behaving` (HeardLabeller)."""
    labeller = HeardLabeller(robot, reach_m, window_s, behaving)
    labelled = [h for episode in episodes for h in labeller.add(episode)]
    return labelled + (labeller.finish() if ended else [])
