"""tvl/SonarRing-v0 used as Gymnasium users misuse environments: vector copies and seeds of
the wrong type get Gymnasium's own words, an episode that has ended takes no step until it
is reset, the human mode needs a display, and the normalised actions are the float32 Box in
[-1, 1] that RL libraries ask for."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest

from tvl_cli.core.drive_command import Command
from tvl_cli.gym import ENV_ID, SonarRingEnv
from tvl_cli.gym.actions import ROBOT, STOP_ACTION

T0 = ROBOT.trajectory_index("T0")


@pytest.mark.parametrize(
    ("num_envs", "error", "message"),
    [
        ("4", TypeError, "num_envs must be an int, actual type: <class 'str'>"),
        (2.0, TypeError, "num_envs must be an int, actual type: <class 'float'>"),
        (True, TypeError, "num_envs must be an int, actual type: <class 'bool'>"),
        (0, ValueError, "num_envs must be 1 or more, actual value: 0"),
    ],
)
def test_make_vec_refuses_a_number_of_copies_that_is_none(
    num_envs: object, error: type[Exception], message: str
) -> None:
    with pytest.raises(error, match=message):
        gymnasium.make_vec(ENV_ID, num_envs=num_envs)


@pytest.mark.parametrize(
    ("seed", "message"),
    [
        (1.5, "Seed must be a python integer or a list of them, actual type: <class 'float'>"),
        ("1", "Seed must be a python integer or a list of them, actual type: <class 'str'>"),
        ([1.5, 2], "Seed must be a python integer, actual type: <class 'float'>"),
        (-1, "Seed must be greater or equal to zero, actual value: -1"),
    ],
)
def test_the_vector_env_refuses_a_seed_as_gymnasium_does(seed: object, message: str) -> None:
    envs = gymnasium.make_vec(ENV_ID, num_envs=2)
    with pytest.raises(gymnasium.error.Error, match=message):
        envs.reset(seed=seed)
    # The refusal changed nothing: a good seed gives what it gives a fresh environment.
    np.testing.assert_array_equal(
        envs.reset(seed=3)[0], gymnasium.make_vec(ENV_ID, num_envs=2).reset(seed=3)[0]
    )


def test_the_single_env_refuses_a_fractional_seed_as_gymnasium_does() -> None:
    with pytest.raises(gymnasium.error.Error, match="Seed must be a python integer"):
        gymnasium.make(ENV_ID).reset(seed=1.5)


def test_no_step_after_a_bump_until_reset() -> None:
    env = gymnasium.make(ENV_ID, world="square")
    env.reset(seed=1)
    terminated = False
    while not terminated:
        _, _, terminated, truncated, info = env.step(T0)
        assert not truncated
    time_s = info["time_s"]
    with pytest.raises(gymnasium.error.ResetNeeded, match=r"ended \(terminated\): call reset"):
        env.step(STOP_ACTION)
    assert env.unwrapped._engine.sim.time_s == time_s  # the refused step moved nothing
    env.reset(options={"continue": True})
    assert env.step(STOP_ACTION)[4]["time_s"] > time_s


def test_no_step_after_the_environments_own_step_limit_until_reset() -> None:
    env = SonarRingEnv("square", max_episode_steps=5)
    env.reset(seed=1)
    ends = [env.step(STOP_ACTION)[3] for _ in range(5)]
    assert ends == [False] * 4 + [True]
    with pytest.raises(gymnasium.error.ResetNeeded, match=r"ended \(truncated\)"):
        env.step(STOP_ACTION)
    env.reset()
    assert env.step(STOP_ACTION)[4]["time_s"] == pytest.approx(0.1)


def test_the_human_mode_with_no_display_is_refused_saying_so(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    for name in ("DISPLAY", "WAYLAND_DISPLAY"):
        monkeypatch.delenv(name, raising=False)
    with pytest.raises(ValueError, match=r"render_mode 'human' opens a window, and there is no"):
        SonarRingEnv("square", render_mode="human")
    assert SonarRingEnv("square").metadata["render_modes"] == ["ansi", "rgb_array"]
    assert "human" in SonarRingEnv.metadata["render_modes"]  # where there is a display


def test_normalised_actions_are_a_float32_box_of_minus_one_to_one() -> None:
    space = gymnasium.make(ENV_ID, action_type="normalised").action_space
    # What Stable-Baselines3's env checker asks of a Box action space, lest it warn: float32,
    # symmetric, and within [-1, 1] (stable_baselines3/common/env_checker.py).
    assert isinstance(space, gymnasium.spaces.Box) and space.dtype == np.float32
    assert (space.low == -1).all() and (space.high == 1).all() and space.shape == (2,)
    vector = gymnasium.make_vec(ENV_ID, num_envs=2, action_type="normalised")
    assert vector.single_action_space == space


def test_a_normalised_action_drives_as_its_fraction_of_the_robots_limits() -> None:
    normalised = gymnasium.make(ENV_ID, world="square", action_type="normalised")
    continuous = gymnasium.make(ENV_ID, world="square", action_type="continuous")
    actions = normalised.unwrapped.robot_task.actions
    assert actions.command(np.array([1.0, -0.5], dtype=np.float32)) == Command(0.6, -0.5)
    normalised.reset(seed=2)
    continuous.reset(seed=2)
    for fraction in ([0.5, 0.25], [1.0, -1.0], [-0.5, 0.0]):
        by_fraction = normalised.step(np.array(fraction, dtype=np.float32))[4]
        speed, turn = fraction[0] * 0.6, fraction[1] * 1.0
        by_command = continuous.step(np.array([speed, turn]))[4]
        np.testing.assert_allclose(by_fraction["pose"], by_command["pose"], atol=1e-7)


def test_a_normalised_action_beyond_one_is_refused_naming_the_range() -> None:
    env = gymnasium.make(ENV_ID, action_type="normalised")
    env.reset(seed=1)
    with pytest.raises(ValueError, match=r"is outside \[-1, 1\], as fractions of the top speed"):
        env.step(np.array([1.5, 0.0], dtype=np.float32))
    with pytest.raises(ValueError, match="speed_fraction is for discrete actions only"):
        gymnasium.make(ENV_ID, action_type="normalised", speed_fraction=0.5)
