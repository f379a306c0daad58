"""Exploratory learning (paper §4.1, Figure 14): follow the least experienced trajectory
slowly until it collides or closes a circle, label every point by deceleration to the
collision point, and train the FAM with the whole episode."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass, field

import numpy as np

from tvl_cli.core.command import Command
from tvl_cli.core.config import RobotConfig, sonars_within
from tvl_cli.core.errors import BadInput, check_minutes
from tvl_cli.core.fam import Fam
from tvl_cli.io.logfile import Episode, mm_to_ring, ring_to_mm
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap
from tvl_cli.training import TrainParams, train_episode

# Backed off along the path after a collision, when learning and when behaving.
BACKOFF_M = 0.15


@dataclass(frozen=True, slots=True)
class LearnParams:
    """How the robot explores; stored with each log session beside the TrainParams."""

    minutes: float = 15.0
    learn_speed_mps: float = 0.2
    straight_run_m: float = 8.0  # a T0 run this long without a bump counts as free
    reverse_m: float = BACKOFF_M  # backed off along the path after a collision
    # A sonar facing ahead of the body's middle reading this close, once the robot has closed
    # in on it, marks a collision point before any bump (paper §5.1: a collision placed
    # further from objects when learning helps). Just above the 0.15 m minimum range, it fires
    # as an object enters the ring's blind zone, so a wall the arc runs into alongside, unseen
    # ahead by the specular ring, counts as a collision too. 0 waits for bumps.
    near_m: float = 0.16

    def __post_init__(self) -> None:
        check_minutes(self.minutes)
        if not (math.isfinite(self.learn_speed_mps) and self.learn_speed_mps > 0):
            raise BadInput(f"--learn-speed {self.learn_speed_mps:g} must be > 0 m/s")
        if not (math.isfinite(self.near_m) and self.near_m >= 0):
            raise BadInput(f"--near {self.near_m:g} must be >= 0 m")

    def to_dict(self) -> dict[str, float]:
        return asdict(self)


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


# How much nearer than at the episode's start a sonar must read before `near_m` counts: well
# above the noise (about 1.2 cm close in), so a wall the robot runs beside but does not
# approach never ends an episode, and one it is leaving behind never does either.
NEAR_CLOSING_M = 0.05


def least_experienced(experience: np.ndarray, rng: np.random.Generator) -> tuple[int, int]:
    """(rotation, trajectory) of the least experienced pair; ties drawn by the generator."""
    flat = experience.ravel()
    candidates = np.flatnonzero(flat == flat.min())
    pick = int(candidates[rng.integers(len(candidates))])
    rotation, trajectory = divmod(pick, experience.shape[1])
    return rotation, trajectory


def backoff_commands(forward: Command, robot: RobotConfig, distance_m: float) -> list[Command]:
    """Commands that drive back along the arc `forward` was following, for distance_m."""
    step_m = forward.linear_mps * robot.control_period_s
    steps = math.ceil(distance_m / step_m - 1e-9)
    return [Command(-forward.linear_mps, -forward.angular_radps)] * steps


def spin_commands(sonar_offset: int, robot: RobotConfig) -> list[Command]:
    """Commands that turn the robot in place to face sonar `sonar_offset` (CCW positive),
    the shorter way round, at its spin rate, ending exactly on the angle."""
    count = robot.sonar.count
    offset = (sonar_offset + count // 2) % count - count // 2  # -8..7
    angle = offset * 2 * math.pi / count
    per_step = robot.spin_rate_radps * robot.control_period_s
    steps = math.ceil(abs(angle) / per_step - 1e-9)
    if steps == 0:
        return []
    return [Command.spin(angle / (steps * robot.control_period_s))] * steps


EpisodeSink = Callable[[Episode], None]
MinuteSink = Callable[[MinuteStats], None]
StopCheck = Callable[[], str | None]


class Learner:
    """One robot exploring one world, training one FAM, handing each episode to a sink."""

    def __init__(
        self,
        world: WorldMap,
        robot: RobotConfig,
        fam: Fam,
        params: LearnParams,
        train_params: TrainParams,
        seed: int,
    ) -> None:
        sim_seed, choice_seed = np.random.SeedSequence(seed).spawn(2)
        self.robot = robot
        self.fam = fam
        self.params = params
        self.train_params = train_params
        self.sim = Simulator(world, robot, np.random.default_rng(sim_seed))
        self.rng = np.random.default_rng(choice_seed)
        # The sonars facing ahead of the body's middle (sideways ones included).
        self._ahead = np.array(sonars_within(math.pi / 2, robot.sonar.count))

    def _too_near(self, ring_m: np.ndarray, start_m: np.ndarray) -> bool:
        """A sonar ahead reads within near_m, having closed in since the episode started."""
        ahead = ring_m[self._ahead]
        closing = ahead < start_m[self._ahead] - NEAR_CLOSING_M
        return bool((closing & (ahead < self.params.near_m)).any())

    def _free_run_m(self, trajectory: int) -> float:
        """How far a trajectory goes before it counts as free: a full circle, or a long run."""
        traj = self.robot.trajectories[trajectory]
        if traj.curvature_per_m == 0:
            return self.params.straight_run_m
        return 2 * math.pi * traj.radius_m

    def _speed(self, trajectory: int) -> float:
        return min(self.params.learn_speed_mps, self.robot.trajectories[trajectory].v_max_mps)

    def episode(self, index: int, deadline_s: float) -> Episode | None:
        """One pass of Figure 14's loop, or None if time ran out before the episode ended."""
        ring_m = mm_to_ring(ring_to_mm(self.sim.read_sonar()))
        _, experience = self.fam.perceive(ring_m)
        rotation, trajectory = least_experienced(experience, self.rng)
        for command in spin_commands(rotation, self.robot):
            self.sim.step(command)

        traj = self.robot.trajectories[trajectory]
        command = Command.follow(traj, self._speed(trajectory))
        step_m = command.linear_mps * self.robot.control_period_s
        free_run_m = self._free_run_m(trajectory)
        rings: list[np.ndarray] = []
        poses: list[tuple[float, float, float]] = []
        odometry: list[tuple[float, float, float]] = []
        arcs: list[float] = []
        arc_m = 0.0
        collided = bumped = False
        while arc_m < free_run_m - 1e-9:
            if self.sim.time_s >= deadline_s:
                return None
            ring_mm = ring_to_mm(self.sim.read_sonar())
            if rings and self._too_near(mm_to_ring(ring_mm), mm_to_ring(rings[0])):
                collided = True
                break
            rings.append(ring_mm)
            poses.append(self.sim.pose)
            odometry.append(self.sim.odometry)
            arcs.append(arc_m)
            self.sim.step(command)
            # Odometry-free arc length: the distance commanded; short and exact (paper §4.1).
            arc_m += step_m
            if self.sim.bumped:
                collided = bumped = True
                break
        sonars = self.robot.sonar.count
        episode = Episode(
            index=index,
            ring_mm=np.array(rings, dtype=np.uint16).reshape(-1, sonars),
            pose=np.array(poses, dtype=np.float64).reshape(-1, 3),
            odometry=np.array(odometry, dtype=np.float64).reshape(-1, 3),
            arc_m=np.array(arcs, dtype=np.float64),
            trajectory=trajectory,
            rotation=rotation,
            collided=collided,
            bumped=bumped,
            end_arc_m=arc_m,
            end_time_s=self.sim.time_s,
        )
        if collided:
            for back in backoff_commands(command, self.robot, self.params.reverse_m):
                self.sim.step(back)
        return episode

    def _velocity_entries(self) -> np.ndarray:
        tables = range(len(self.fam.config.tables))
        return np.concatenate([self.fam.velocity_table(t).ravel() for t in tables])

    def run(
        self,
        on_episode: EpisodeSink,
        on_minute: MinuteSink,
        should_stop: StopCheck = lambda: None,
    ) -> LearnSummary:
        """Learn until the simulated minutes are spent or `should_stop` names a reason."""
        summary = LearnSummary()
        deadline_s = self.params.minutes * 60.0
        steps_per_minute = 60.0 / self.robot.control_period_s
        last = math.ceil(deadline_s / 60.0)  # minutes 0 .. last - 1 are recorded
        minute = MinuteStats(0)
        while self.sim.time_s < deadline_s:
            summary.stopped_by = should_stop()
            if summary.stopped_by:
                break
            episode = self.episode(summary.episodes, deadline_s)
            if episode is None:
                break
            before = self._velocity_entries()
            train_episode(self.fam, episode, self.robot, self.train_params)
            change = float(np.abs(self._velocity_entries() - before).mean())
            on_episode(episode)
            # The last minute keeps an episode ending on its closing boundary.
            while episode.end_time_s >= (minute.minute + 1) * 60.0 and minute.minute + 1 < last:
                on_minute(minute)
                summary.minutes.append(minute)
                minute = MinuteStats(minute.minute + 1)
            minute.episodes += 1
            minute.collisions += int(episode.bumped)
            minute.exemplars += episode.exemplar_count
            minute.delta_v += change / steps_per_minute
            summary.episodes += 1
            summary.collisions += int(episode.bumped)
            summary.exemplars += episode.exemplar_count
        if summary.stopped_by is None:
            # The last minute is whole only when time ran out; a cut-short one is partial.
            while minute.minute < last:
                on_minute(minute)
                summary.minutes.append(minute)
                minute = MinuteStats(minute.minute + 1)
        summary.sim_s = self.sim.time_s
        return summary
