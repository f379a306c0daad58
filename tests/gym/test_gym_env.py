"""tvl/SonarRing-v0 on real pymunk worlds: Gymnasium's checker, spaces, rewards, seeding,
episodes that go on after a bump, pictures, and vectorised use."""

from __future__ import annotations

import math
import re
from dataclasses import replace
from pathlib import Path

import gymnasium
import numpy as np
import pytest
from doc_pages import page
from gymnasium.utils.env_checker import check_env

from tvl_cli.agent.engine import GOAL_RADIUS_M
from tvl_cli.core.drive_command import STOP, Command
from tvl_cli.core.learn_params import BACKOFF_M
from tvl_cli.core.memory import NO_MEMORY, MemoryConfig
from tvl_cli.core.method import DEFAULT, PAPER
from tvl_cli.core.reward import COLLISION_PENALTY_M, step_reward
from tvl_cli.core.robot_config import SONAR_MODELS
from tvl_cli.gym import ENV_ID, MAX_EPISODE_STEPS, SonarRingEnv
from tvl_cli.gym.env import ACTION_NAMES, ROBOT, SPIN_LEFT, SPIN_RIGHT, STOP_ACTION
from tvl_cli.render.animate import DPI, FIGURE_SIZE_IN

ROOT = Path(__file__).resolve().parents[2]
WORLDS = ROOT / "worlds"
T0 = ROBOT.trajectory_index("T0")
# The square's start: (2.125, 2.125) facing +x, inner wall faces at 0.25 and 3.75 m. The ring
# sits on the body's edge, so the wall ahead is 1.425 m from S0, the one behind 1.675 m.
AHEAD_M, BEHIND_M = 3.75 - 2.125 - ROBOT.radius_m, 2.125 - 0.25 - ROBOT.radius_m


# Ours with the live ring: what the robot observes is what its sonars read now, which the
# tests check against the walls.
LIVE_RING = replace(DEFAULT, memory=NO_MEMORY)


def make(**kwargs: object) -> gymnasium.Env:
    return gymnasium.make(ENV_ID, **{"world": "square", "method": LIVE_RING, **kwargs})


def straight_into_the_wall(env: gymnasium.Env) -> list[tuple]:
    """Every step of driving T0 from the start until the episode ends."""
    steps = []
    for _ in range(100):
        steps.append(env.step(T0))
        if steps[-1][2] or steps[-1][3]:
            return steps
    raise AssertionError("drove 10 s straight without meeting the wall")


@pytest.mark.parametrize(
    "kwargs", [{"task": "avoid"}, {"task": "goal", "world": "obstacles"}], ids=["avoid", "goal"]
)
def test_the_env_passes_gymnasiums_checker(
    kwargs: dict[str, str], monkeypatch: pytest.MonkeyPatch
) -> None:
    # Unwrapped, as the checker asks, render check and all, on a machine with no display.
    # Any warning fails the test (pytest runs with warnings as errors). The human mode's
    # window is checked under a display server (tests/gym/test_gym_window.py).
    for name in ("DISPLAY", "WAYLAND_DISPLAY"):
        monkeypatch.delenv(name, raising=False)
    env = make(**kwargs)
    check_env(env.unwrapped)
    env.close()


def test_a_bundled_name_and_a_file_path_give_the_same_world() -> None:
    by_name, by_path = make(), make(world=str(WORLDS / "square.txt"))
    assert by_name.unwrapped.world.segments == by_path.unwrapped.world.segments
    np.testing.assert_array_equal(by_name.reset(seed=3)[0], by_path.reset(seed=3)[0])


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"task": "wander"}, "unknown task 'wander'"),
        ({"world": "worlds/missing.txt"}, "missing.txt: cannot read"),
        ({"world": "sqare"}, "no bundled world 'sqare'"),
        ({"goal": (1.0, 1.0)}, "goal is for task 'goal' only"),
        ({"task": "goal"}, "square: world has no goal"),
        ({"task": "goal", "goal": (9.0, 9.0)}, "goal 9,9"),
        ({"speed_fraction": 0.0}, r"speed_fraction 0.0 is outside \(0, 1\]"),
        ({"render_mode": "window"}, "unknown render_mode 'window'"),
    ],
)
def test_bad_constructor_input_is_a_value_error(kwargs: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        SonarRingEnv(**{"world": "square", **kwargs})


def test_the_observation_is_the_sonar_ring_in_metres() -> None:
    env = make()
    obs, info = env.reset(seed=1)
    assert env.observation_space.shape == (16,) and obs.dtype == np.float32
    assert obs in env.observation_space
    # Sonar noise is 0.01 m + 1 % of the range: well inside 0.1 m at these ranges.
    assert obs[0] == pytest.approx(AHEAD_M, abs=0.1)  # S0, ahead
    assert obs[4] == pytest.approx(AHEAD_M, abs=0.1)  # S4, to the left (the north wall)
    assert obs[8] == pytest.approx(BEHIND_M, abs=0.1)
    assert obs[12] == pytest.approx(BEHIND_M, abs=0.1)
    np.testing.assert_array_equal(info["pose"], [2.125, 2.125, 0.0])


def test_the_actions_are_the_trajectories_then_a_spin_each_way_and_a_stop() -> None:
    env = SonarRingEnv("square", speed_fraction=0.5)
    assert env.action_space.n == 10
    assert env.commands[T0] == Command(0.3, 0.0)
    assert env.commands[0] == Command(0.175, 0.175 / 0.5)  # T3L: 0.5 m radius, to the left
    assert env.commands[6] == Command(0.175, -0.175 / 0.5)  # T3R
    assert env.commands[SPIN_LEFT] == Command(0.0, ROBOT.spin_rate_radps)
    assert env.commands[SPIN_RIGHT] == Command(0.0, -ROBOT.spin_rate_radps)
    assert env.commands[STOP_ACTION] == STOP
    env.reset(seed=1)
    x, y, heading = env.step(T0)[4]["pose"]
    assert (x, y, heading) == pytest.approx((2.125 + 0.03, 2.125, 0.0))  # 0.3 m/s for 0.1 s
    assert env.step(SPIN_LEFT)[4]["pose"] == pytest.approx((x, y, 0.1))
    assert env.step(STOP_ACTION)[4]["pose"] == pytest.approx((x, y, 0.1))


def test_avoid_rewards_forward_metres_and_ends_at_a_bump_with_the_baselines_penalty() -> None:
    env = make()
    _, info = env.reset(seed=1)
    odometry = [info["odometry"]]
    steps = straight_into_the_wall(env)
    odometry += [step[4]["odometry"] for step in steps]
    rewards = [step[1] for step in steps]
    *driving, (_, last_reward, terminated, truncated, last_info) = steps
    assert terminated and not truncated and last_info["bumped"] and "bump" in last_info["events"]
    assert not any(step[2] or step[4]["bumped"] for step in driving)
    # Each reward is the one the Q-learning baseline learns by, from the odometry before and
    # after.
    bumped = [False] * len(driving) + [True]
    assert rewards == [
        step_reward(tuple(a), tuple(b), bump)
        for a, b, bump in zip(odometry[:-1], odometry[1:], bumped, strict=True)
    ]
    assert last_reward < -COLLISION_PENALTY_M + 0.07  # at most one step's 0.06 m
    assert sum(rewards) == pytest.approx(AHEAD_M - COLLISION_PENALTY_M, abs=0.05)
    assert last_info["pose"][0] == pytest.approx(3.75 - ROBOT.radius_m, abs=0.01)


def test_goal_rewards_progress_by_odometry_until_the_goal_is_reached() -> None:
    env = make(task="goal", goal=(3.0, 2.125))
    obs, info = env.reset(seed=1)
    assert obs.shape == (18,) and obs in env.observation_space
    assert obs[16:] == pytest.approx((0.0, 0.875), abs=1e-6)  # straight ahead, 0.875 m away
    steps = straight_into_the_wall(env)
    obs, _, terminated, _, info = steps[-1]
    assert terminated and info["goal_reached"] and not info["bumped"]
    # Reached within 0.3 m: 0.575 m at 0.06 m a step.
    assert len(steps) == math.ceil((0.875 - 0.3) / 0.06)
    remaining_m = math.dist(info["odometry"][:2], (3.0, 2.125))
    assert obs[17] == pytest.approx(remaining_m, abs=1e-6)
    assert sum(step[1] for step in steps) == pytest.approx(0.875 - remaining_m)
    env.reset(seed=1)
    turned = env.step(SPIN_LEFT)[0]
    assert turned[16] == pytest.approx(-0.1, abs=0.005)  # the goal now lies to the right
    assert env.step(SPIN_LEFT)[1] == pytest.approx(0.0, abs=1e-3)  # turning makes no progress


def test_the_same_seed_gives_the_same_episode_and_another_seed_another() -> None:
    def episode(seed: int) -> list[np.ndarray]:
        env = make()
        env.action_space.seed(0)
        seen = [env.reset(seed=seed)[0]]
        for _ in range(150):
            obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
            seen += [obs, np.array([reward]), info["pose"], info["odometry"]]
            if terminated or truncated:
                seen.append(env.reset()[0])
        return seen

    first, again, other = episode(5), episode(5), episode(6)
    assert all(np.array_equal(a, b) for a, b in zip(first, again, strict=True))
    assert not np.array_equal(first[0], other[0])  # the noise differs from the start


def test_continue_backs_off_from_the_bump_and_keeps_the_clock() -> None:
    env = make()
    env.reset(seed=1)
    bumped_at = straight_into_the_wall(env)[-1][4]
    obs, info = env.reset(options={"continue": True})
    # Backed off along the path by at least 0.15 m: three steps of 0.06 m.
    assert info["pose"][0] == pytest.approx(bumped_at["pose"][0] - 0.18, abs=0.01)
    assert info["time_s"] == pytest.approx(bumped_at["time_s"] + 0.3)
    assert obs[0] == pytest.approx(0.18, abs=0.05)  # the wall just ahead again
    with pytest.raises(ValueError, match="takes none"):
        env.reset(seed=2, options={"continue": True})
    with pytest.raises(ValueError, match="nothing to continue"):
        make().reset(options={"continue": True})


def test_an_episode_lasts_at_most_a_competence_run() -> None:
    env = make()
    env.reset(seed=1)
    for step in range(MAX_EPISODE_STEPS):
        *_, terminated, truncated, info = env.step(STOP_ACTION)
        assert not terminated and truncated == (step == MAX_EPISODE_STEPS - 1)
    assert info["time_s"] == pytest.approx(300.0)


def test_rgb_array_draws_the_replay_frame_and_ansi_the_numbers() -> None:
    env = make(render_mode="rgb_array")
    env.reset(seed=1)
    start = env.render()
    width_in, height_in = FIGURE_SIZE_IN
    assert start.shape == (round(height_in * DPI), round(width_in * DPI), 3)
    assert start.dtype == np.uint8
    env.step(T0)
    moved = env.render()
    assert (moved != start).any(axis=2).sum() > 100  # the robot, its rays and the bars moved
    text = make(render_mode="ansi")
    obs, _ = text.reset(seed=1)
    obs, *_ = text.step(SPIN_RIGHT)
    lines = text.render().splitlines()
    assert lines[0].startswith("0.1 s  x 2.12 m  y 2.12 m  heading -6°")
    assert re.fullmatch(r"action spin-right, reward [+-]0\.000", lines[1])  # no progress
    assert [float(r) for r in lines[2].split()[2:]] == pytest.approx(obs, abs=0.005)


def test_it_runs_under_sync_vector_env_with_each_copy_seeded_apart() -> None:
    envs = gymnasium.vector.SyncVectorEnv([make, make])
    obs, _ = envs.reset(seed=7)
    assert obs.shape == (2, 16)
    # The copies are seeded 7 and 8, each as a single environment with that seed would be.
    for k, seed in enumerate((7, 8)):
        np.testing.assert_array_equal(obs[k], make().reset(seed=seed)[0])
    for _ in range(100):
        obs, _, terminated, _, info = envs.step(np.array([T0, T0]))
        if terminated.all():
            break
    assert terminated.all() and info["bumped"].all()
    # Autoreset: the next step puts both copies back at the start, the wall 1.425 m ahead.
    obs, rewards, terminated, _, info = envs.step(np.array([T0, T0]))
    np.testing.assert_array_equal(rewards, [0.0, 0.0])
    np.testing.assert_array_equal(info["pose"], [[2.125, 2.125, 0.0]] * 2)
    assert obs[:, 0] == pytest.approx([AHEAD_M] * 2, abs=0.1)
    envs.close()


def test_the_docs_quote_the_envs_own_numbers() -> None:
    # Words compared across line breaks, so rewrapping the page does not matter.
    gym = " ".join(page("guide/gym.md").split())
    sonar = ROBOT.sonar
    assert (
        f"{sonar.min_range_m:g}–{sonar.max_range_m:.1f} for the default robot; "
        f"{sonar.max_range_m:.1f} means no echo" in gym
    )
    assert f"`Discrete({len(ACTION_NAMES)})`" in gym
    assert f"at {ROBOT.spin_rate_radps:g} rad/s" in gym
    # One reward per task: avoid, goal and wall each charge the bump.
    assert gym.count(f"less {COLLISION_PENALTY_M:g} for a bump") == 3
    assert f"within {GOAL_RADIUS_M:g} m of the goal" in gym
    assert f"after {MAX_EPISODE_STEPS:,} steps" in gym
    assert f"backed off {BACKOFF_M:g} m along its path after a bump" in gym


def test_the_gymnasium_observation_is_the_methods_virtual_ring() -> None:
    plain = make(world="lab")
    ours = gymnasium.make("tvl/SonarRing-v0", world="lab")  # the default method, as tvl run's
    assert ours.unwrapped.method == DEFAULT and DEFAULT.memory != NO_MEMORY
    remembering = make(
        world="lab", method=replace(DEFAULT, memory=MemoryConfig("patches", window_s=20.0))
    )
    a, _ = plain.reset(seed=3)
    b, _ = remembering.reset(seed=3)
    np.testing.assert_array_equal(ours.reset(seed=3)[0], b)
    # The same seed reads the same rings; the virtual one is never farther.
    assert (b <= a).all()
    nearer = False
    for _ in range(60):
        a, _, bumped, *_ = plain.step(3)
        b, *_ = remembering.step(3)
        assert (b <= a).all()
        nearer |= bool((b < a).any())
        if bumped:  # the same drive bumps both: an episode that ended takes no more steps
            break
    assert nearer


def test_the_method_is_given_whole_by_preset_or_by_file(tmp_path: Path) -> None:
    assert SonarRingEnv("square", method="paper").method == PAPER
    assert SonarRingEnv("square", method="default").method == DEFAULT
    assert SonarRingEnv("square").method == DEFAULT
    chosen = tmp_path / "ideal.toml"
    chosen.write_text('sonar = "ideal"\nmemory = "none"\nreflexes = "none"\n')
    env = SonarRingEnv("square", method=chosen)
    assert env.method == replace(DEFAULT, sonar="ideal", memory=NO_MEMORY, reflexes=())
    assert env.robot.sonar == SONAR_MODELS["ideal"]
    a, _ = env.reset(seed=1)
    np.testing.assert_array_equal(a, env.reset(seed=2)[0])  # the ideal ring draws no noise
    assert SonarRingEnv("square", method=str(chosen)).method == env.method
    with pytest.raises(ValueError, match="method 'lines': neither a preset"):
        SonarRingEnv("square", method="lines")
    with pytest.raises(TypeError, match="method 3 is not a Method"):
        SonarRingEnv("square", method=3)  # type: ignore[arg-type]
    bad = tmp_path / "bad.toml"
    bad.write_text('sonar = "sharp"\n')
    with pytest.raises(ValueError, match=rf"{re.escape(str(bad))}: sonar 'sharp'"):
        SonarRingEnv("square", method=bad)
    unknown = tmp_path / "unknown.toml"
    unknown.write_text("decel = 0.2\n")
    with pytest.raises(ValueError, match="unknown key 'decel'"):
        gymnasium.make_vec(ENV_ID, num_envs=2, method=unknown)
