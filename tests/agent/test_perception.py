"""The echo memory: what the FAM reads is the live ring, or nearer where something was heard a
moment ago, placed by odometry alone."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from tvl_cli.agent.drive import Step
from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.explore import Learner
from tvl_cli.agent.perception import EchoMemory, Perception, perceived_episodes, replayed_rings
from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.memory import (
    GOAL_BEAMS_EITHER_SIDE,
    NO_MEMORY,
    NOT_CHOSEN,
    PATCHES,
    POINTS,
    MemoryChoice,
    MemoryConfig,
)
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.ring import mm_to_ring
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.worldmap import load_world

ROOT = Path(__file__).resolve().parents[2]
ROBOT = RobotConfig()
NAMES = [t.name for t in ROBOT.trajectories]
MAX = ROBOT.sonar.max_range_m
PATCH_MEMORY = MemoryConfig(PATCHES, window_s=20.0)


def silent() -> np.ndarray:
    return np.full(16, MAX)


def test_without_a_memory_the_fam_reads_the_live_ring_itself() -> None:
    perception = Perception(NO_MEMORY, ROBOT)
    ring = np.random.default_rng(1).uniform(0.15, 4.0, 16)
    assert perception.sense(0.0, (1.0, 2.0, 0.3), ring) is ring
    assert perception.peek(0.1, (1.0, 2.0, 0.3), ring) is ring


@pytest.mark.parametrize("kind", [POINTS, PATCHES])
def test_a_memory_never_reads_farther_than_the_live_ring(kind: str) -> None:
    rng = np.random.default_rng(2)
    perception = Perception(MemoryConfig(kind, window_s=3.0), ROBOT)
    pose = np.zeros(3)
    for step in range(200):
        pose += rng.normal(0.0, [0.05, 0.05, 0.2])
        ring = np.where(rng.random(16) < 0.5, rng.uniform(0.15, 4.0, 16), MAX)
        virtual = perception.sense(step * 0.1, tuple(pose), ring)
        assert np.all(virtual <= ring)
        assert np.all(virtual >= ROBOT.sonar.min_range_m)


def test_a_wall_heard_square_on_is_read_by_the_sonar_that_now_faces_it() -> None:
    # Facing +x with a long wall 1 m to the left (y = 1.2 from the body's centre), S4 (90°)
    # hears it square on. Half a metre on, by odometry, S3 (67.5°) meets the remembered patch
    # although the live ring reads nothing there.
    memory = EchoMemory(MemoryConfig(PATCHES, window_s=5.0, range_m=2.0, patch_m=3.0), ROBOT)
    heard = silent()
    heard[4] = 1.0
    memory.remember(0, (0.0, 0.0, 0.0), heard)
    virtual = memory.virtual(5, (0.5, 0.0, 0.0), silent())
    wall_y = ROBOT.radius_m + 1.0
    # S3's transducer sits on the body's edge at 67.5°; the nearest of its rays to the wall is
    # the one nearest the wall's normal, 80° off the heading.
    from_transducer = wall_y - ROBOT.radius_m * math.sin(math.radians(67.5))
    assert virtual[4] == pytest.approx(1.0)
    assert virtual[3] == pytest.approx(from_transducer / math.sin(math.radians(80.0)), rel=1e-9)
    assert virtual[0] == MAX  # ahead is still open


def test_a_remembered_echo_is_placed_by_odometry_not_by_where_the_robot_truly_is() -> None:
    # The same readings at the same odometry give the same virtual ring: the memory is handed
    # no true pose at all. Moving the odometry moves what is remembered with it.
    ring = silent()
    ring[0] = 1.0
    first, second = (EchoMemory(PATCH_MEMORY, ROBOT) for _ in range(2))
    first.remember(0, (0.0, 0.0, 0.0), ring)
    second.remember(0, (0.0, 0.0, 0.0), ring)
    assert np.array_equal(
        first.virtual(1, (0.3, 0.0, 0.0), silent()), second.virtual(1, (0.3, 0.0, 0.0), silent())
    )
    # Odometry 0.3 m further on: the wall ahead is 0.3 m nearer.
    assert first.virtual(1, (0.3, 0.0, 0.0), silent())[0] == pytest.approx(0.7)


def test_echoes_older_than_the_window_are_forgotten() -> None:
    memory = EchoMemory(MemoryConfig(PATCHES, window_s=1.0), ROBOT)
    ring = silent()
    ring[0] = 1.0
    memory.remember(0, (0.0, 0.0, 0.0), ring)
    assert memory.virtual(9, (0.0, 0.0, 0.0), silent())[0] == pytest.approx(1.0)
    assert memory.virtual(10, (0.0, 0.0, 0.0), silent())[0] == MAX


def test_echoes_beyond_the_memory_range_are_not_remembered() -> None:
    memory = EchoMemory(MemoryConfig(PATCHES, range_m=1.5), ROBOT)
    ring = silent()
    ring[[0, 4]] = (2.0, 1.0)
    memory.remember(0, (0.0, 0.0, 0.0), ring)
    virtual = memory.virtual(1, (0.0, 0.0, 0.0), silent())
    assert virtual[0] == MAX and virtual[4] == pytest.approx(1.0)


def test_a_patch_is_heard_only_from_the_side_it_was_heard_from() -> None:
    # Heard ahead 1 m away, then (by odometry) the robot is beyond it, facing back: the
    # patch's back faces it and reads nothing.
    memory = EchoMemory(PATCH_MEMORY, ROBOT)
    ring = silent()
    ring[0] = 1.0
    memory.remember(0, (0.0, 0.0, 0.0), ring)
    assert memory.virtual(1, (2.5, 0.0, math.pi), silent())[0] == MAX


def test_points_are_read_only_inside_a_beams_cone() -> None:
    memory = EchoMemory(MemoryConfig(POINTS), ROBOT)
    ring = silent()
    ring[0] = 1.0  # a point 1.2 m ahead of the centre
    memory.remember(0, (0.0, 0.0, 0.0), ring)
    assert memory.virtual(1, (0.0, 0.0, 0.0), silent())[0] == pytest.approx(1.0)
    # Turned 20° left, the point lies 20° right of S0's axis: outside its 12.5° half cone.
    assert memory.virtual(1, (0.0, 0.0, math.radians(20.0)), silent())[0] == MAX


def _session_steps(minutes: float, memory: MemoryConfig) -> tuple[list[Episode], list[Step]]:
    world = load_world(ROOT / "worlds" / "lab.txt")
    episodes: list[Episode] = []
    steps: list[Step] = []
    learner = Learner(
        world,
        ROBOT,
        Fam(SINGLE, NAMES),
        LearnParams(minutes=minutes),
        replace(DEFAULT, memory=memory),
        3,
    )
    learner.run(episodes.append, lambda _minute: None, on_step=steps.append)
    return episodes, steps


@pytest.mark.slow
def test_learning_trains_on_virtual_rings_that_replaying_its_exemplars_rebuilds() -> None:
    episodes, _ = _session_steps(2.0, PATCH_MEMORY)
    assert all(e.fam_ring_m is not None for e in episodes)
    steps = np.concatenate([e.steps(ROBOT.control_period_s) for e in episodes])
    assert np.all(np.diff(steps) > 0)  # exemplars in time order, each on a step of its own
    replayed = replayed_rings(
        PATCH_MEMORY,
        ROBOT,
        steps,
        np.concatenate([e.odometry for e in episodes]),
        mm_to_ring(np.concatenate([e.ring_mm for e in episodes])),
    )
    learnt = np.concatenate([e.fam_ring_m for e in episodes if e.fam_ring_m is not None])
    np.testing.assert_array_equal(replayed, learnt)
    # The memory heard things the live ring missed.
    assert (learnt < mm_to_ring(np.concatenate([e.ring_mm for e in episodes]))).any()


def test_an_episodes_exemplars_are_the_steps_before_it_ended() -> None:
    episodes, steps = _session_steps(1.0, NO_MEMORY)
    dt = ROBOT.control_period_s
    read_on = {round(s.time_s / dt) for s in steps if s.ring_m is not None}
    for episode in episodes:
        assert set(episode.steps(dt).tolist()) <= read_on


def test_a_run_through_a_memory_reads_nearer_than_the_ring_and_differs_from_one_without() -> None:
    world = load_world(ROOT / "worlds" / "lab.txt")
    fam = Fam(SINGLE, NAMES, max(ROBOT.v_max_mps))
    perceived: list[Step] = []
    behave(
        world,
        ROBOT,
        fam,
        "avoid",
        minutes=1.0,
        seed=2,
        on_step=perceived.append,
        method=replace(DEFAULT, memory=PATCH_MEMORY),
    )
    virtual = [s for s in perceived if s.decision.perceived_m is not None]
    assert virtual
    assert all(np.all(s.decision.perceived_m <= s.ring_m) for s in virtual if s.ring_m is not None)
    assert any(np.any(s.decision.perceived_m < s.ring_m) for s in virtual if s.ring_m is not None)


def test_memory_settings_are_checked() -> None:
    with pytest.raises(BadInput, match="--memory lines"):
        MemoryConfig("lines")
    with pytest.raises(BadInput, match="--memory-window 0"):
        MemoryConfig(PATCHES, window_s=0.0)
    with pytest.raises(BadInput, match="--memory-range -1"):
        MemoryConfig(PATCHES, range_m=-1.0)
    with pytest.raises(BadInput, match="unknown echo memory setting 'depth'"):
        MemoryConfig.from_dict({"kind": "points", "depth": 3})
    choices = "choose never, goal, toward-goal, always"
    with pytest.raises(BadInput, match=f"--memory-clearing sometimes: {choices}"):
        MemoryConfig(PATCHES, clearing="sometimes")
    with pytest.raises(BadInput, match=f"clearing 1: {choices}"):
        MemoryConfig.from_dict({"kind": "patches", "clearing": 1})


def test_a_memory_recorded_before_clearing_was_a_choice_never_clears() -> None:
    recorded = {"kind": "patches", "window_s": 20.0, "range_m": 4.0, "patch_m": 0.3}
    assert MemoryConfig.from_dict(recorded).clearing == "never"
    assert DEFAULT.memory.clearing == "toward-goal"
    assert MemoryConfig.from_dict(DEFAULT.memory.to_dict()) == DEFAULT.memory


def test_no_memory_is_one_memory_whatever_its_settings() -> None:
    assert MemoryConfig("none", window_s=30.0) == NO_MEMORY
    assert MemoryConfig("none", clearing="always") == NO_MEMORY


def test_a_choice_replaces_only_the_settings_given() -> None:
    base = MemoryConfig(PATCHES, window_s=20.0, range_m=3.0)
    assert NOT_CHOSEN.over(base) == base
    assert MemoryChoice(window_s=7.0).over(base) == MemoryConfig(PATCHES, 7.0, 3.0)
    assert MemoryChoice(kind="none").over(base) == NO_MEMORY
    assert MemoryChoice(clearing="always").over(base) == replace(base, clearing="always")


@pytest.mark.slow
def test_replaying_a_log_session_gives_each_episode_its_virtual_rings(tmp_path: Path) -> None:
    from tvl_cli.commands.learn import LearnRequest, learn_to_log
    from tvl_cli.io.log_sessions import finished_episodes
    from tvl_cli.io.logreader import read_log

    log = tmp_path / "lab.h5"
    learn_to_log(
        LearnRequest(
            ROOT / "worlds" / "lab.txt",
            log,
            3,
            "single",
            LearnParams(minutes=1.0),
            replace(DEFAULT, memory=PATCH_MEMORY),
        )
    )
    (session,) = read_log(log).sessions
    assert session.method.memory == PATCH_MEMORY
    online, _ = _session_steps(1.0, PATCH_MEMORY)
    replayed = perceived_episodes(session.episodes(), PATCH_MEMORY, ROBOT)
    assert len(replayed) == len(online)
    for mine, theirs in zip(replayed, online, strict=True):
        np.testing.assert_array_equal(mine.fam_rings(), theirs.fam_rings())
    # A snapshot replays the memory only as far as its cut, and reads what the whole
    # replay read up to there: nothing after the cut changes what was read before it.
    cut_s = replayed[len(replayed) // 2].end_time_s
    snapshot = perceived_episodes(finished_episodes(session, cut_s), PATCH_MEMORY, ROBOT)
    assert 0 < len(snapshot) < len(replayed)
    assert all(e.end_time_s <= cut_s for e in snapshot)
    for mine, whole in zip(snapshot, replayed, strict=False):
        np.testing.assert_array_equal(mine.fam_rings(), whole.fam_rings())


def _pillar_heard_from(distance_m: float, memory: EchoMemory) -> None:
    """S0 hears a pillar `distance_m` ahead of the body's edge, from the origin facing +x."""
    heard = silent()
    heard[0] = distance_m
    memory.remember(0, (0.0, 0.0, 0.0), heard)


@pytest.mark.parametrize("clears", [False, True])
def test_a_beam_that_hears_farther_clears_a_wide_patch_only_when_clearing(clears: bool) -> None:
    # A pillar heard 2 m ahead is remembered as a patch as wide as the beam there (0.89 m).
    # Turned 20° to the left, S0's cone still holds the patch's right end, though the live
    # beam hears a wall 3 m away: the patch closes that way, unless a live echo clears it.
    memory = EchoMemory(PATCH_MEMORY, ROBOT, clears=clears)
    _pillar_heard_from(2.0, memory)
    live = silent()
    live[0] = 3.0
    virtual = memory.virtual(1, (0.0, 0.0, math.radians(20.0)), live)
    if clears:
        assert virtual[0] == 3.0
    else:
        assert 2.0 < virtual[0] < 2.6  # the patch's end, nearer than the live echo


def test_clearing_keeps_a_patch_heard_from_near_and_every_patch_in_a_silent_beam() -> None:
    # Heard from 0.5 m, the patch is no wider than the beam was there (0.3 m, the floor): it
    # stays in a beam that hears farther. A wide patch stays in a beam that hears nothing,
    # since a slanted wall is silent.
    near = EchoMemory(PATCH_MEMORY, ROBOT, clears=True)
    _pillar_heard_from(0.5, near)
    live = silent()
    live[0] = 3.0
    assert near.virtual(1, (0.0, 0.0, 0.0), live)[0] == pytest.approx(0.5)
    far = EchoMemory(PATCH_MEMORY, ROBOT, clears=True)
    _pillar_heard_from(2.0, far)
    assert far.virtual(1, (0.0, 0.0, math.radians(20.0)), silent())[0] < 2.6


@pytest.mark.parametrize("goal_deg", [0.0, 20.0, -20.0, 90.0, None])
def test_toward_the_goal_a_beam_that_hears_farther_meets_no_patch_even_one_heard_near(
    goal_deg: float | None,
) -> None:
    # The patch of a pillar heard 0.5 m ahead is narrow (0.3 m), and clearing keeps it. With
    # the goal beyond it, S0, facing the goal (the nearest its bearing, or as near as
    # GOAL_BEAMS_EITHER_SIDE), hears a wall 3 m away and so reads 3 m; the goal off to the
    # side, or none, S0 still meets the patch.
    memory = EchoMemory(replace(PATCH_MEMORY, clearing="toward-goal"), ROBOT, True, True)
    _pillar_heard_from(0.5, memory)
    live = silent()
    live[0] = 3.0
    bearing = None if goal_deg is None else math.radians(goal_deg)
    virtual = memory.virtual(1, (0.0, 0.0, 0.0), live, bearing)
    facing = goal_deg is not None and abs(round(goal_deg / 22.5)) <= GOAL_BEAMS_EITHER_SIDE
    assert virtual[0] == (3.0 if facing else pytest.approx(0.5))
    # A silent beam facing the goal still meets every patch: a slanted wall is silent.
    silent_ring = memory.virtual(1, (0.0, 0.0, 0.0), silent(), bearing)
    assert silent_ring[0] == pytest.approx(0.5)


@pytest.mark.parametrize(
    ("clearing", "seeking_goal", "opens"),
    [("toward-goal", True, True), ("toward-goal", False, False), ("goal", True, False)],
)
def test_perception_opens_toward_the_goal_only_when_seeking_one_with_that_clearing(
    clearing: str, seeking_goal: bool, opens: bool
) -> None:
    perception = Perception(replace(PATCH_MEMORY, clearing=clearing), ROBOT, seeking_goal)
    ring = silent()
    ring[0] = 0.5
    perception.sense(0.0, (0.0, 0.0, 0.0), ring)
    live = silent()
    live[0] = 3.0
    virtual = perception.sense(0.1, (0.0, 0.0, 0.0), live, goal_xy=(5.0, 0.0))
    assert (virtual[0] == 3.0) == opens


@pytest.mark.parametrize(
    ("clearing", "seeking_goal", "clears"),
    [
        ("never", True, False),
        ("goal", False, False),
        ("goal", True, True),
        ("toward-goal", False, False),
        ("toward-goal", True, True),
        ("always", False, True),
    ],
)
def test_perception_clears_as_the_memory_says_for_its_behaviour(
    clearing: str, seeking_goal: bool, clears: bool
) -> None:
    config = replace(PATCH_MEMORY, clearing=clearing)
    perception = Perception(config, ROBOT, seeking_goal=seeking_goal)
    ring = silent()
    ring[0] = 2.0
    perception.sense(0.0, (0.0, 0.0, 0.0), ring)
    live = silent()
    live[0] = 3.0
    virtual = perception.peek(0.1, (0.0, 0.0, math.radians(20.0)), live)
    assert (virtual[0] == 3.0) == clears


def test_a_learner_replays_its_rings_cleared_only_when_the_memory_always_clears() -> None:
    rng = np.random.default_rng(7)
    steps = np.arange(60)
    odometry = np.cumsum(rng.normal(0.0, [0.05, 0.05, 0.2], (60, 3)), axis=0)
    rings = np.where(rng.random((60, 16)) < 0.6, rng.uniform(0.3, 3.5, (60, 16)), MAX)
    replayed = {
        c: replayed_rings(replace(PATCH_MEMORY, clearing=c), ROBOT, steps, odometry, rings)
        for c in ("never", "goal", "toward-goal", "always")
    }
    np.testing.assert_array_equal(replayed["never"], replayed["goal"])
    np.testing.assert_array_equal(replayed["never"], replayed["toward-goal"])
    assert (replayed["always"] != replayed["never"]).any()
    assert np.all(replayed["always"] >= replayed["never"])  # clearing only lets farther in
