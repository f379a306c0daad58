"""Learning while behaving: the collision-point estimate, its confirmation by a bump or a near
point, and the FAM the behaviour drives with learning as it goes."""

from __future__ import annotations

import functools
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from doc_pages import page, section

from tvl_cli.agent.drive import Step, drive
from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.explore import Learner
from tvl_cli.agent.online import (
    BUMP,
    ECHO_AFTER_S,
    ECHO_BEFORE_S,
    ESTIMATED,
    FREE,
    NEAR,
    OnlineLearner,
)
from tvl_cli.agent.policy import Decision, Observation
from tvl_cli.core.drive_command import Command
from tvl_cli.core.episode import Episode
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.training import TrainParams
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import load_world

ROOT = Path(__file__).resolve().parents[2]
SQUARE = load_world(ROOT / "worlds" / "square.txt")
ROBOT = RobotConfig()
NAMES = [t.name for t in ROBOT.trajectories]
T0 = ROBOT.trajectory_index("T0")
R = ROBOT.radius_m
# The square's walls are one 0.25 m cell thick round a 4 m map: inner faces at 0.25 and 3.75.
EAST_WALL_X, SOUTH_WALL_Y = 3.75, 0.25
LIVE_RING = replace(DEFAULT, memory=NO_MEMORY)  # our method, perceiving the live ring


@functools.cache
def _learnt_tables() -> tuple[list[np.ndarray], list[np.ndarray]]:
    """A minute of exploring the square: velocity and experience tables."""
    fam = Fam(SINGLE, NAMES)
    learner = Learner(SQUARE, ROBOT, fam, LearnParams(minutes=1), LIVE_RING, seed=1)
    learner.run(lambda _episode: None, lambda _minute: None)
    tables = range(len(SINGLE.tables))
    return [fam.velocity_table(t) for t in tables], [fam.experience_table(t) for t in tables]


def trained_fam() -> Fam:
    """A fresh copy of the FAM a minute of exploring the square learnt."""
    return Fam.from_tables(SINGLE, NAMES, *_learnt_tables())


class Straight:
    """Drives T0 at a speed for some steps, reading the ring, then spins on the spot."""

    def __init__(self, speed_mps: float, steps: int) -> None:
        self.command = Command.follow(ROBOT.trajectories[T0], speed_mps)
        self.steps = steps

    def decide(self, obs: Observation) -> Decision:
        obs.ring.get()  # read, as a policy driving by its sonars does
        if self.steps <= 0:
            return Decision(Command.spin(0.5))
        self.steps -= 1
        return Decision(self.command, trajectory=T0, choice=T0)

    def interrupt(self) -> None:
        pass


def drive_straight(
    pose: tuple[float, float, float], speed_mps: float, steps: int
) -> tuple[list[Episode], OnlineLearner]:
    sim = Simulator(SQUARE, ROBOT, np.random.default_rng(3))
    sim.place(*pose)
    episodes: list[Episode] = []
    learner = OnlineLearner(trained_fam(), ROBOT, TrainParams(), pose, episodes.append)
    # Then spinning for long enough that the estimate is made (ECHO_AFTER_S later).
    spin_steps = round(ECHO_AFTER_S / ROBOT.control_period_s) + 5
    minutes = (steps + spin_steps) * ROBOT.control_period_s / 60.0
    drive(sim, Straight(speed_mps, steps), minutes, on_step=learner)
    return episodes, learner


def test_the_estimate_for_a_straight_run_at_a_wall_is_the_true_distance() -> None:
    start = SQUARE.start  # facing the east wall from the middle
    episodes, learner = drive_straight(start, 0.3, 20)
    (episode,) = episodes
    true_m = EAST_WALL_X - start[0] - R
    assert learner.summary().endings[ESTIMATED] == 1
    assert episode.collided and not episode.bumped
    # The nearest of 20 noisy returns of the wall (sigma 1 cm + 1 % of the 1.6 m range): on
    # the near side of the truth, by about two sigma, never past it.
    assert true_m - 0.08 < episode.end_arc_m < true_m
    assert episode.exemplar_count == 20
    np.testing.assert_allclose(episode.arc_m, 0.03 * np.arange(20))


def test_a_bump_confirms_the_collision_point_where_it_touched() -> None:
    # Heading 8.6° down at the south wall, 0.15 m off it: the front sonars meet the wall
    # too obliquely to hear it, so nothing ahead reads the blind zone, and the body touches
    # it after 0.15 / sin(0.15) m.
    heading = -0.15
    y = SOUTH_WALL_Y + R + 0.15
    episodes, learner = drive_straight((2.0, y, heading), 0.2, 60)
    approach, *pressing = episodes
    assert approach.collided and approach.bumped
    true_m = 0.15 / math.sin(-heading)
    # Sensed after the step that touched: at most one step (0.02 m) past the true point.
    assert true_m - 1e-6 <= approach.end_arc_m <= true_m + 0.02 + 1e-6
    assert approach.end_arc_m == pytest.approx(approach.arc_m[-1] + 0.02)
    # Driving on against the wall, every step is a collision point one step ahead.
    assert learner.summary().endings[BUMP] == 1 + len(pressing) > 1
    assert all(e.bumped and e.exemplar_count == 1 for e in pressing)


def step(
    k: int, ring_m: np.ndarray, command: Command, trajectory: int, bumped: bool = False
) -> Step:
    pose = (0.02 * k, 0.0, 0.0)
    return Step(0.1 * k, ring_m, Decision(command, trajectory=trajectory), pose, pose, bumped, ())


def test_a_near_point_ends_the_stretch_where_the_blind_zone_was_read() -> None:
    episodes: list[Episode] = []
    learner = OnlineLearner(trained_fam(), ROBOT, TrainParams(), (0.0, 0.0, 0.0), episodes.append)
    forward = Command.follow(ROBOT.trajectories[T0], 0.2)
    clear = np.full(16, 4.0)  # nothing heard anywhere
    blind = clear.copy()
    blind[1] = ROBOT.sonar.min_range_m  # 22.5° left of ahead, inside its blind zone
    for k in range(4):
        learner(step(k, clear, forward, T0))
    learner(step(4, blind, forward, T0))
    (episode,) = episodes
    assert learner.summary().endings[NEAR] == 1
    assert episode.collided and not episode.bumped
    assert episode.exemplar_count == 4  # the blind reading is no exemplar
    assert episode.end_arc_m == pytest.approx(0.08)  # where the blind zone was read


def test_a_stretch_with_nothing_heard_on_its_arc_is_free() -> None:
    episodes: list[Episode] = []
    learner = OnlineLearner(trained_fam(), ROBOT, TrainParams(), (0.0, 0.0, 0.0), episodes.append)
    forward = Command.follow(ROBOT.trajectories[T0], 0.2)
    for k in range(3):
        learner(step(k, np.full(16, 4.0), forward, T0))
    learner(step(3, np.full(16, 4.0), Command.spin(0.5), -1))
    assert not episodes  # the estimate waits for what the ring hears next
    learner.finish(0.4)
    (episode,) = episodes
    assert learner.summary().endings[FREE] == 1
    assert not episode.collided
    assert np.isinf(episode.distances_m()).all()


def test_the_policy_drives_with_the_fam_as_it_learns() -> None:
    fam, untouched = trained_fam(), trained_fam()
    learner = OnlineLearner(fam, ROBOT, TrainParams(), SQUARE.start)
    seen: list[Step] = []

    def watch(s: Step) -> None:
        seen.append(s)
        learner(s)

    behave(SQUARE, ROBOT, fam, "avoid", minutes=1.0, seed=2, on_step=watch, method=LIVE_RING)
    assert learner.summary().episodes > 10
    perceived = [
        (s.decision.velocities, untouched.perceive(s.ring_m)[0][s.decision.rotation % 16])
        for s in seen
        if s.ring_m is not None and s.decision.velocities is not None
    ]
    # The first decisions, before any stretch ended, perceive as the FAM file did; later
    # ones perceive with what the run has learnt.
    np.testing.assert_array_equal(*perceived[0])
    assert any(not np.allclose(ours, theirs) for ours, theirs in perceived)
    ring = np.full(16, 1.0)
    assert not np.array_equal(fam.velocities(ring[None, :]), untouched.velocities(ring[None, :]))


def test_the_same_seed_learns_the_same_episodes() -> None:
    def learnt() -> list[Episode]:
        episodes: list[Episode] = []
        fam = trained_fam()
        learner = OnlineLearner(fam, ROBOT, TrainParams(), SQUARE.start, episodes.append)
        behave(
            SQUARE, ROBOT, fam, "wall-left", minutes=0.5, seed=4, on_step=learner, method=LIVE_RING
        )
        return episodes

    first, second = learnt(), learnt()
    assert len(first) == len(second) > 3
    for a, b in zip(first, second, strict=True):
        np.testing.assert_array_equal(a.ring_mm, b.ring_mm)
        np.testing.assert_array_equal(a.arc_m, b.arc_m)
        assert (a.trajectory, a.end_arc_m, a.collided) == (b.trajectory, b.end_arc_m, b.collided)


def test_the_docs_quote_the_readings_the_estimate_uses() -> None:
    behaving = section(page("guide/behaving.md"), "Learning while behaving (`tvl run --learn`)")
    assert f"estimated {ECHO_AFTER_S:g} s later" in behaving
    assert (
        f"from {ECHO_BEFORE_S:g} s before the\n  stretch ended to {ECHO_AFTER_S:g} s after"
        in behaving
    )
