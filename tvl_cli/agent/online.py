"""Learning while behaving (paper §4, and the future work §5 ends on): whatever behaviour
drives the robot, estimate the collision point of the trajectory it is driving from the
sonar returns accumulated along the way and odometry, and train the FAM it drives with on
every stretch it drove.

`OnlineLearner` is a step observer (a drive loop's `on_step`), so the loop and the policy stay
as they are and the learner reads only what the run read anyway: a run that learns draws the
same sonar and odometry noise as one that does not, until the first update changes a choice.

A *stretch* is a run of consecutive steps driving forward along one trajectory. Each step
whose ring was read is an exemplar, at the arc length commanded so far (as exploration counts
it, paper §4.1). The stretch ends
- at a bump during one of its steps: the collision point is there, exactly;
- at a near point, a sonar within 45° of ahead reading inside its blind zone (what a run
  counts as a near miss, core.contacts): the collision point is where that reading was taken;
- when the robot stops driving that trajectory (another choice, a spin, a back-off, the end
  of the run): the collision point is estimated, ECHO_AFTER_S later. The sonar returns read
  from ECHO_BEFORE_S before the stretch ended to ECHO_AFTER_S after it are points in the
  odometry frame, and the estimate is the first point along the arc, continued from where the
  stretch ended, at which the body would meet one of them. None within a full circle (for T0:
  anywhere ahead, which the 4 m ring covers well past where labels stop changing) makes the
  stretch free, and every exemplar is labelled the trajectory's maximum.
The stretch becomes an Episode, labelled and trained as exploration's are (core.training), in
the order the stretches ended: by the heard rule, every trajectory at each exemplar from the
echoes heard 10 s either side of it, the driven one no farther than the stretch's own
collision point, once those echoes are in; by the paper's rule, the driven trajectory alone,
at once.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from tvl_cli.agent.drive import Step
from tvl_cli.agent.perception import Perception
from tvl_cli.agent.policy import Pose
from tvl_cli.agent.recording import EpisodeRecord
from tvl_cli.core.arcs import first_contact_m
from tvl_cli.core.contacts import blind_ahead, near_miss_sonars
from tvl_cli.core.episode import Episode
from tvl_cli.core.fam import Fam
from tvl_cli.core.memory import NO_MEMORY, MemoryConfig
from tvl_cli.core.ring import mm_to_ring, ring_to_mm
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.training import SessionTrainer, TrainParams

# The sonar returns a stretch's collision point is estimated from: those read from a moment
# before it ended to a while after (benchmarks/online_estimate.py measures the choice). The
# specular ring hears a wall only near square on, so a wall the arc meets at a slant is often
# heard only once the robot has turned away from it, and the estimate waits for that; a
# longer past keeps more returns placed off their objects (a corner heard at the edge of a
# cone is put on its axis) and makes estimates too near. In rooms worlds, 5 s before and none
# after left 7 % of the estimates over 0.3 m too far (10 s before: 3 % too far, 10 % too
# near); 2 s before and 3 s after, 1 % too far and 2 % too near.
ECHO_BEFORE_S = 2.0
ECHO_AFTER_S = 3.0

# How a stretch's collision point was found, as the learner counts them.
BUMP, NEAR, ESTIMATED, FREE = "bump", "near", "estimated", "free"
ENDINGS = (BUMP, NEAR, ESTIMATED, FREE)

EpisodeSink = Callable[[Episode], None]


class EchoWindow:
    """The sonar returns of the last `window_s` of control steps, as points in the odometry
    frame: each reading on its transducer's axis, at its range from the body's edge.

    A reading at the maximum range heard nothing and adds no point; one at the minimum range
    (the blind zone) is placed there, the nearest the ring can tell.
    """

    def __init__(self, robot: RobotConfig, window_s: float) -> None:
        count = robot.sonar.count
        self._steps = max(1, round(window_s / robot.control_period_s))
        self._points = np.full((self._steps, count, 2), np.nan)  # (W, 16, 2) metres; NaN: none
        self._next = 0
        self._sonar_rad = np.arange(count) * (2 * math.pi / count)  # (16,) from the heading
        self._body_m = robot.radius_m  # transducers sit on the body's edge
        self._max_range_m = robot.sonar.max_range_m

    def add(self, odometry: Pose, ring_m: np.ndarray | None) -> None:
        """One control step: the ring read at `odometry` (None: not read this step)."""
        row = self._points[self._next]
        self._next = (self._next + 1) % self._steps
        if ring_m is None:
            row[...] = np.nan
            return
        x, y, theta = odometry
        reach = np.where(ring_m < self._max_range_m, self._body_m + ring_m, np.nan)  # (16,) m
        angle = theta + self._sonar_rad
        row[:, 0] = x + reach * np.cos(angle)
        row[:, 1] = y + reach * np.sin(angle)

    def points(self) -> np.ndarray:
        """(K, 2) metres: every return in the window."""
        flat = self._points.reshape(-1, 2)
        return flat[~np.isnan(flat[:, 0])]


@dataclass(frozen=True, slots=True)
class OnlineSummary:
    """What a run learnt: its episodes, their exemplars, and how their collision points
    were found (ENDINGS)."""

    episodes: int
    exemplars: int
    endings: dict[str, int]


@dataclass(slots=True)
class _Stretch(EpisodeRecord):
    """A stretch, recorded step by step as it is driven, then waiting to be labelled."""

    # Once it has ended:
    end_time_s: float = 0.0
    end_odometry: Pose = (0.0, 0.0, 0.0)  # where it ended, the arc's continuation starts
    ending: str = ""  # BUMP or NEAR when confirmed; "" while the estimate waits
    end_arc_m: float = 0.0  # the confirmed collision point
    ready_step: int = 0  # the learner's step count from which it can be labelled


class OnlineLearner:
    """Watches a behaviour's steps, turns each driven stretch into an episode, trains `fam`
    with it (the very FAM the policy perceives with) and hands it to `on_episode`."""

    def __init__(
        self,
        fam: Fam,
        robot: RobotConfig,
        params: TrainParams,
        start: Pose,
        on_episode: EpisodeSink = lambda episode: None,
        before_s: float = ECHO_BEFORE_S,
        after_s: float = ECHO_AFTER_S,
        memory: MemoryConfig = NO_MEMORY,
    ) -> None:
        self.fam = fam
        # The virtual rings the FAM trains on remember the exemplars' readings alone, so
        # that `tvl train` makes the same of the log's exemplars.
        self._perception = Perception(memory, robot)
        self.robot = robot
        self._trainer = SessionTrainer(fam, robot, params, behaving=True)
        self._on_episode = on_episode
        # Read when the estimate is made, after_s after the stretch ended, the window reaches
        # back to before_s before it ended.
        self._echoes = EchoWindow(robot, before_s + after_s)
        self._after_steps = round(after_s / robot.control_period_s)
        self._near_sonars = near_miss_sonars(robot.sonar.count)
        # The true pose and odometry before the next step: the world's start, where the
        # simulator places the robot and starts its odometry.
        self._pose: Pose = start
        self._odometry: Pose = start
        self._steps = 0
        self._stretch: _Stretch | None = None
        self._ended: deque[_Stretch] = deque()  # in the order they ended, to be labelled
        self._episodes = 0
        self._exemplars = 0
        self._endings = dict.fromkeys(ENDINGS, 0)

    def __call__(self, step: Step) -> None:
        ring = step.ring_m
        self._echoes.add(self._odometry, ring)
        decision = step.decision
        follows = decision.trajectory >= 0 and decision.command.linear_mps > 0.0
        near = ring is not None and blind_ahead(
            ring, self._near_sonars, self.robot.sonar.min_range_m
        )
        stretch = self._stretch
        if stretch is not None:
            if near:
                self._end(step.time_s, NEAR, stretch.arc_m)
            elif not follows or decision.trajectory != stretch.trajectory:
                self._end(step.time_s)
        # A step reading its blind zone is no exemplar: the ring cannot tell how near it is.
        if follows and not near:
            stretch = self._stretch or self._begin(decision.trajectory, decision.rotation)
            if ring is not None:
                ring_mm = ring_to_mm(ring)
                perceived = (
                    self._perception.sense(step.time_s, self._odometry, mm_to_ring(ring_mm))
                    if self._perception.remembers
                    else None
                )
                stretch.record(ring_mm, self._pose, self._odometry, perceived)
            stretch.arc_m += decision.command.linear_mps * self.robot.control_period_s
            if step.bumped:
                self._end(step.time_s + self.robot.control_period_s, BUMP, stretch.arc_m)
        self._pose, self._odometry = step.pose, step.odometry
        self._steps += 1
        while self._ended and self._ended[0].ready_step <= self._steps:
            self._learn(self._ended.popleft())

    def finish(self, time_s: float) -> None:
        """The run has ended: the stretch under way ends, and every stretch still waiting for
        its estimate takes it from what has been heard."""
        if self._stretch is not None:
            self._end(time_s)
        while self._ended:
            self._learn(self._ended.popleft())
        self._trainer.finish()

    def summary(self) -> OnlineSummary:
        return OnlineSummary(self._episodes, self._exemplars, dict(self._endings))

    def _begin(self, trajectory: int, rotation: int) -> _Stretch:
        self._stretch = _Stretch(trajectory, rotation % self.robot.sonar.count)
        return self._stretch

    def _end(self, time_s: float, ending: str = "", end_arc_m: float = 0.0) -> None:
        """End the stretch under way where the robot is now: confirmed (`ending`), or to be
        estimated once ECHO_AFTER_S more of returns are in."""
        stretch, self._stretch = self._stretch, None
        assert stretch is not None
        if not stretch.arcs:
            return  # the ring was not read on it: nothing to learn
        stretch.end_time_s, stretch.end_odometry = time_s, self._odometry
        stretch.ending, stretch.end_arc_m = ending, end_arc_m
        stretch.ready_step = self._steps + (0 if ending else self._after_steps)
        self._ended.append(stretch)

    def _estimate(self, stretch: _Stretch) -> tuple[str, float]:
        """The stretch's collision point from the echoes, by the arc continued from its end."""
        curvature = self.robot.trajectories[stretch.trajectory].curvature_per_m
        ahead_m = first_contact_m(
            stretch.end_odometry, curvature, self._echoes.points(), self.robot.radius_m
        )
        if math.isinf(ahead_m):
            return FREE, stretch.arc_m
        return ESTIMATED, stretch.arc_m + ahead_m

    def _learn(self, stretch: _Stretch) -> None:
        """Label the stretch, train the FAM with it and hand it on."""
        ending, end_arc_m = (
            (stretch.ending, stretch.end_arc_m) if stretch.ending else self._estimate(stretch)
        )
        episode = stretch.episode(
            self._episodes,
            self.robot.sonar.count,
            collided=ending != FREE,
            bumped=ending == BUMP,
            end_arc_m=end_arc_m,
            end_time_s=stretch.end_time_s,
        )
        self._trainer.add(episode)  # trained now, or once its labels are heard
        self._on_episode(episode)
        self._episodes += 1
        self._exemplars += episode.exemplar_count
        self._endings[ending] += 1
