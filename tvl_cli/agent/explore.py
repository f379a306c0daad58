"""Exploratory learning (paper §4.1, Figure 14): follow the least experienced trajectory
slowly until it collides or closes a circle, label every point by deceleration to the
collision point, and train the FAM with the whole episode.

Where a method chooses otherwise, the choice comes from the registries beside this module:
which pair to follow (agent.explore_rules) and where else a collision point is placed
(agent.collision_points)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from tvl_cli.agent.collision_points import sonar_collision_points
from tvl_cli.agent.drive import StepSink, drive
from tvl_cli.agent.explore_rules import EXPLORATION_RULES
from tvl_cli.agent.motions import backoff_commands, spin_commands
from tvl_cli.agent.perception import Perception
from tvl_cli.agent.policy import Decision, Observation, Pose
from tvl_cli.agent.recording import EpisodeRecord
from tvl_cli.core.drive_command import Command
from tvl_cli.core.episode import Episode
from tvl_cli.core.fam import Fam
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.method import DEFAULT, Method
from tvl_cli.core.ring import mm_to_ring, ring_to_mm
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.training import SessionTrainer, Trained, train_params
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap


@dataclass(slots=True)
class MinuteStats:
    """Learning progress in one simulated minute."""

    minute: int
    episodes: int = 0
    collisions: int = 0
    exemplars: int = 0
    delta_v: float = 0.0  # paper eq. 4: mean |change| of the velocity entries per control step


@dataclass(slots=True)
class LearnSummary:
    episodes: int = 0
    collisions: int = 0
    exemplars: int = 0
    sim_s: float = 0.0
    minutes: list[MinuteStats] = field(default_factory=list)
    stopped_by: str | None = None  # what cut learning short (a signal name), if anything


EpisodeSink = Callable[[Episode], None]
MinuteSink = Callable[[MinuteStats], None]
StopCheck = Callable[[], str | None]


class ExplorePolicy:
    """Figure 14 as a policy: face the least experienced of the 112 (rotation, trajectory)
    pairs (or another, by the method's exploration rule), follow it slowly recording every
    step, end the episode at a collision point (a bump, or where the method's sonar
    collision points say) or a full circle, hand it on, and after a collision reverse along
    the path."""

    def __init__(
        self,
        robot: RobotConfig,
        fam: Fam,
        params: LearnParams,
        rng: np.random.Generator,
        true_pose: Callable[[], Pose],
        on_episode: EpisodeSink,
        perception: Perception | None = None,
        method: Method = DEFAULT,
    ) -> None:
        self.robot = robot
        self.fam = fam
        self.params = params
        self.rng = rng
        # What the FAM reads. Only the exemplars' readings are remembered, so that replaying
        # the log's exemplars (`tvl train`) rebuilds exactly the virtual rings learnt from.
        self.perception = perception or Perception(method.memory, robot)
        # The log keeps the true pose for people to draw; no choice is made by it.
        self._true_pose = true_pose
        self._on_episode = on_episode
        self._sonar_points = sonar_collision_points(robot, method.near_m)
        self.rule = EXPLORATION_RULES[method.exploration](robot, method)
        self._queue: list[Command] = []  # a spin to face the choice, or a back-off
        self._following: Decision | None = None
        self._last_follow: Command | None = None
        self._episode = EpisodeRecord(0, 0)
        self.episodes = 0

    @property
    def between_episodes(self) -> bool:
        """Nothing under way: a good moment to stop."""
        return self._following is None and not self._queue

    def interrupt(self) -> None:
        """A reflex moved the robot off the path: the episode under way no longer describes
        one trajectory, so it is dropped."""
        self._queue, self._following = [], None

    def decide(self, obs: Observation) -> Decision:
        self.rule.visit(obs.odometry)
        if self._queue:
            return Decision(self._queue.pop(0))
        following = self._following
        # The log's millimetres, once per step: the online FAM perceives exactly what is logged.
        ring_mm = ring_to_mm(obs.ring_m)
        # An episode is judged once it has recorded a step (a bump while spinning to face
        # the trajectory is no collision point on it).
        if following is not None and self._episode.rings and self._episode_over(obs, ring_mm):
            following = None
            if self._queue:
                return Decision(self._queue.pop(0))
        if following is None:
            following = self._start(ring_mm, obs)
            if self._queue:
                return Decision(self._queue.pop(0))
        record = self._episode
        perceived = (
            self.perception.sense(obs.time_s, obs.odometry, mm_to_ring(ring_mm))
            if self.perception.remembers
            else None
        )
        record.record(ring_mm, self._true_pose(), obs.odometry, perceived)
        # Odometry-free arc length: the distance commanded; short and exact (paper §4.1).
        record.arc_m += following.command.linear_mps * self.robot.control_period_s
        return following

    def _episode_over(self, obs: Observation, ring_mm: np.ndarray) -> bool:
        """End the episode under way if the last step bumped, came too near or closed a
        circle; hand it on."""
        record = self._episode
        bumped = obs.bumped
        near = False
        if not bumped and record.arc_m < self._free_run_m(record.trajectory) - 1e-9:
            near = (
                self._sonar_points is not None
                and bool(record.rings)
                and self._sonar_points.reached(mm_to_ring(ring_mm), mm_to_ring(record.rings[0]))
            )
            if not near:
                return False
        collided = bumped or near
        self._on_episode(
            record.episode(
                self.episodes,
                self.robot.sonar.count,
                collided=collided,
                bumped=bumped,
                end_arc_m=record.arc_m,
                end_time_s=obs.time_s,
            )
        )
        self.episodes += 1
        self._following = None
        if collided and self._last_follow is not None:
            self._queue = backoff_commands(self._last_follow, self.robot, self.params.reverse_m)
        return True

    def _start(self, ring_mm: np.ndarray, obs: Observation) -> Decision:
        """Choose a pair, spin to face it, and set off along it."""
        seen = self.perception.peek(obs.time_s, obs.odometry, mm_to_ring(ring_mm))
        rotation, trajectory = self.choose(seen, obs.odometry)
        self._queue = spin_commands(rotation, self.robot)
        self._episode = EpisodeRecord(trajectory, rotation)
        self._last_follow = Command.follow(
            self.robot.trajectories[trajectory], self._speed(trajectory)
        )
        self._following = Decision(self._last_follow, trajectory=trajectory, choice=trajectory)
        return self._following

    def choose(self, ring_m: np.ndarray, odometry: Pose) -> tuple[int, int]:
        """The (rotation, trajectory) pair to set off along next, by the exploration rule,
        seeing `ring_m` (16,) metres at `odometry`."""
        _, experience = self.fam.perceive(ring_m)
        return self.rule.choose(experience, ring_m, odometry, self.rng)

    def _free_run_m(self, trajectory: int) -> float:
        """How far a trajectory goes before it counts as free: a full circle, or a long run."""
        traj = self.robot.trajectories[trajectory]
        if traj.curvature_per_m == 0:
            return self.params.straight_run_m
        return 2 * math.pi * traj.radius_m

    def _speed(self, trajectory: int) -> float:
        return min(self.params.learn_speed_mps, self.robot.trajectories[trajectory].v_max_mps)


class Learner:
    """One robot exploring one world, training one FAM, handing each episode to a sink."""

    def __init__(
        self,
        world: WorldMap,
        robot: RobotConfig,
        fam: Fam,
        params: LearnParams,
        method: Method,
        seed: int,
        seed_stream: int = 0,
        symmetric: bool = True,
    ) -> None:
        """Learn by `method`'s choices of learning (its labels, collision points, exploration
        rule and echo memory); the robot's sonar is the caller's."""
        # Stream k of a seed is its children 2k and 2k + 1 (what spawn() would hand out
        # next): a log's second session goes on from its first instead of repeating it.
        sim_seed, choice_seed = (
            np.random.SeedSequence(seed, spawn_key=(2 * seed_stream + i,)) for i in (0, 1)
        )
        self.robot = robot
        self.fam = fam
        self.params = params
        self.method = method
        self.train_params = train_params(method, symmetric, fam.init_velocity_mps)
        self.sim = Simulator(world, robot, np.random.default_rng(sim_seed))
        self.rng = np.random.default_rng(choice_seed)

    def run(
        self,
        on_episode: EpisodeSink,
        on_minute: MinuteSink,
        should_stop: StopCheck = lambda: None,
        on_step: StepSink | None = None,
    ) -> LearnSummary:
        """Learn until the simulated minutes are spent or `should_stop` names a reason; each
        step shown to `on_step` if given (a live view)."""
        tally = _Tally(
            SessionTrainer(self.fam, self.robot, self.train_params),
            self.fam.entry_count,
            on_episode,
            on_minute,
            60.0 / self.robot.control_period_s,
            math.ceil(self.params.minutes),
        )
        policy = ExplorePolicy(
            self.robot,
            self.fam,
            self.params,
            self.rng,
            lambda: self.sim.pose,
            tally.learnt,
            Perception(self.method.memory, self.robot),
            self.method,
        )
        summary = tally.summary

        def stop() -> bool:
            if not policy.between_episodes:
                return False
            summary.stopped_by = should_stop()
            return summary.stopped_by is not None

        drive(self.sim, policy, self.params.minutes, on_step=on_step, stop=stop, measure=False)
        if summary.stopped_by is None:
            # The session has ended: what waits for its labels is trained. A session stopped
            # by a signal leaves it to `tvl train` (the log keeps it), so that it stops at once.
            tally.finish()
        summary.sim_s = self.sim.time_s
        return summary


class _Tally:
    """A session's counts as its episodes are learnt: the whole session's, and each simulated
    minute's, handed on as the minute closes."""

    def __init__(
        self,
        trainer: SessionTrainer,
        entries: int,
        on_episode: EpisodeSink,
        on_minute: MinuteSink,
        steps_per_minute: float,
        last: int,
    ) -> None:
        self.summary = LearnSummary()
        self._trainer = trainer
        self._entries = entries  # the FAM's velocity entries: delta_v is a mean over them
        self._on_episode = on_episode
        self._on_minute = on_minute
        self._steps_per_minute = steps_per_minute
        self._last = last  # minutes 0 .. last - 1 are recorded
        self._minute = MinuteStats(0)

    def learnt(self, episode: Episode) -> None:
        """Train on an episode, hand it on and count it."""
        # Minutes this episode ended after are closed before it is handed on, so a sink sees
        # each minute when it has seen exactly the episodes counted by then. The last minute
        # keeps an episode ending on its closing boundary.
        minute = self._minute
        while episode.end_time_s >= (minute.minute + 1) * 60.0 and minute.minute + 1 < self._last:
            minute = self._close_minute()
        self._trained(self._trainer.add(episode))
        self._on_episode(episode)
        minute.episodes += 1
        minute.collisions += int(episode.bumped)
        minute.exemplars += episode.exemplar_count
        self.summary.episodes += 1
        self.summary.collisions += int(episode.bumped)
        self.summary.exemplars += episode.exemplar_count

    def finish(self) -> None:
        """Train what waits for its labels, and close the minutes left: the last is whole only
        when time ran out, a cut-short one partial."""
        self._trained(self._trainer.finish())
        while self._minute.minute < self._last:
            self._close_minute()

    def _trained(self, changes: list[Trained]) -> None:
        # The mean over every velocity entry; training sums the change of those it touched.
        # An episode trained once its labels were heard counts in the minute it was trained in.
        for _, change in changes:
            self._minute.delta_v += change / self._entries / self._steps_per_minute

    def _close_minute(self) -> MinuteStats:
        """Hand on the minute under way; the next one."""
        self._on_minute(self._minute)
        self.summary.minutes.append(self._minute)
        self._minute = MinuteStats(self._minute.minute + 1)
        return self._minute
