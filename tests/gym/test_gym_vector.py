"""tvl/SonarRing-v0's vector environment: spaces, shapes and dtypes, seeding, and every copy
step for step as the single environment under Gymnasium's SyncVectorEnv, autoresets too."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

from tvl_cli.gym import ENV_ID, MAX_EPISODE_STEPS, SonarRingEnv, SonarRingVectorEnv
from tvl_cli.gym.env import ROBOT, SPIN_LEFT, STOP_ACTION

T0 = ROBOT.trajectory_index("T0")
COPIES = 4


def make_pair(**kwargs: object) -> tuple[gymnasium.vector.VectorEnv, gymnasium.vector.VectorEnv]:
    """The vector environment and SyncVectorEnv over single environments, alike."""
    kwargs = {"world": "square", **kwargs}
    ours = gymnasium.make_vec(ENV_ID, num_envs=COPIES, **kwargs)
    theirs = gymnasium.make_vec(ENV_ID, num_envs=COPIES, vectorization_mode="sync", **kwargs)
    return ours, theirs


def assert_same(ours: tuple, theirs: tuple) -> None:
    """What reset or step returned: the arrays, values and dtypes, then the info."""
    for mine, other in zip(ours[:-1], theirs[:-1], strict=True):
        assert mine.dtype == other.dtype and mine.shape == other.shape
        assert mine.tobytes() == other.tobytes()
    assert ours[-1].keys() == theirs[-1].keys()
    for key, value in theirs[-1].items():
        np.testing.assert_array_equal(ours[-1][key], value, err_msg=key)


def test_make_vec_makes_it_with_the_single_envs_spaces() -> None:
    envs = gymnasium.make_vec(ENV_ID, num_envs=COPIES, world="obstacles", task="goal")
    single = gymnasium.make(ENV_ID, world="obstacles", task="goal")
    assert isinstance(envs.unwrapped, SonarRingVectorEnv)
    assert envs.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    assert envs.single_observation_space == single.observation_space
    assert envs.single_action_space == single.action_space
    assert envs.action_space.shape == (COPIES,)
    obs, info = envs.reset(seed=1)
    assert obs.shape == (COPIES, 18) and obs.dtype == np.float32 and obs in envs.observation_space
    obs, rewards, terminated, truncated, info = envs.step(envs.action_space.sample())
    assert obs in envs.observation_space
    assert rewards.shape == (COPIES,) and rewards.dtype == np.float64
    assert terminated.dtype == truncated.dtype == np.bool_
    assert info["pose"].shape == (COPIES, 3)


@pytest.mark.slow
@pytest.mark.parametrize(
    "kwargs",
    [{}, {"world": "obstacles", "task": "goal"}, {"world": "lab", "method": "paper"}],
    ids=["avoid", "goal", "paper"],
)
def test_each_copy_steps_as_a_single_env_through_autoresets(kwargs: dict[str, str]) -> None:
    ours, theirs = make_pair(**kwargs)
    assert_same(ours.reset(seed=4), theirs.reset(seed=4))
    rng = np.random.default_rng(1)
    ended = 0
    for _ in range(150):
        actions = rng.integers(ours.single_action_space.n, size=COPIES)
        mine, other = ours.step(actions), theirs.step(actions)
        assert_same(mine, other)
        ended += int((other[2] | other[3]).sum())
    assert ended >= 2  # bumps ended episodes, and the copies were reset on their next step


@pytest.mark.slow
@pytest.mark.parametrize("world", ["square", "obstacles"])
def test_continue_goes_on_in_each_copy_as_in_single_envs(world: str) -> None:
    # Whenever a copy's episode ends, every copy goes on from where it is: the bumped ones
    # backed off first (each its own number of steps, by the speed it hit at), the rest as
    # they stand. Each copy gives what a single environment given the same calls gives.
    ours = SonarRingVectorEnv(COPIES, world=world)
    singles = [SonarRingEnv(world) for _ in range(COPIES)]
    mine = ours.reset(seed=7)
    theirs = [env.reset(seed=7 + i) for i, env in enumerate(singles)]
    assert_copies(mine, theirs)
    rng = np.random.default_rng(2)
    continued = backed_off = 0
    for _ in range(100):
        # Mostly T0 and its neighbours, fast into walls: bumps at different speeds.
        actions = rng.choice([T0 - 1, T0, T0, T0 + 1, SPIN_LEFT], size=COPIES)
        mine = ours.step(actions)
        theirs = [env.step(int(a)) for env, a in zip(singles, actions, strict=True)]
        assert_copies(mine, theirs)
        if mine[2].any():
            before = mine[-1]["time_s"].copy()
            mine = ours.reset(options={"continue": True})
            theirs = [env.reset(options={"continue": True}) for env in singles]
            assert_copies(mine, theirs)
            continued += 1
            backed_off += int((mine[-1]["time_s"] > before).sum())
            # A copy that did not end goes on where it stood, its clock running on.
            assert (mine[-1]["time_s"] >= before).all()
    assert continued >= 10 and backed_off >= 10


def assert_copies(ours: tuple, theirs: list[tuple]) -> None:
    """What the vector environment returned, copy by copy, as each single one did."""
    for i, single in enumerate(theirs):
        for mine, other in zip(ours[:-1], single[:-1], strict=True):
            np.testing.assert_array_equal(mine[i], other)
        for key, value in single[-1].items():
            np.testing.assert_array_equal(ours[-1][key][i], value, err_msg=key)


def test_the_same_seed_gives_the_same_steps_and_copies_differ() -> None:
    def run(seed: int) -> list[np.ndarray]:
        envs = gymnasium.make_vec(ENV_ID, num_envs=COPIES, world="lab")
        seen = [envs.reset(seed=seed)[0]]
        for _ in range(20):
            seen.append(envs.step(np.full(COPIES, T0))[0])
        return seen

    first, again, other = run(5), run(5), run(6)
    assert all(np.array_equal(a, b) for a, b in zip(first, again, strict=True))
    assert not np.array_equal(first[0], other[0])
    assert not np.array_equal(first[0][0], first[0][1])  # each copy its own noise


@pytest.mark.slow  # over a second
def test_episodes_are_truncated_at_the_registered_length() -> None:
    envs = gymnasium.make_vec(ENV_ID, num_envs=2, world="square")
    envs.reset(seed=1)
    for step in range(MAX_EPISODE_STEPS):
        *_, terminated, truncated, info = envs.step(np.full(2, STOP_ACTION))
        assert not terminated.any() and truncated.all() == (step == MAX_EPISODE_STEPS - 1)
    _, rewards, _, truncated, info = envs.step(np.full(2, STOP_ACTION))  # the autoreset
    assert not truncated.any() and (rewards == 0.0).all() and (info["time_s"] == 0.0).all()


def test_bad_use_is_refused() -> None:
    with pytest.raises(ValueError, match="unknown task 'wander'"):
        SonarRingVectorEnv(2, task="wander")
    with pytest.raises(ValueError, match="num_envs must be 1 or more, actual value: 0"):
        SonarRingVectorEnv(0)
    envs = SonarRingVectorEnv(2)
    with pytest.raises(gymnasium.error.ResetNeeded):
        envs.step(np.zeros(2, dtype=np.int64))
    with pytest.raises(ValueError, match="3 seeds for 2 copies"):
        envs.reset(seed=[1, 2, 3])
    envs.reset(seed=1)
    with pytest.raises(ValueError, match="actions of shape"):
        envs.step(np.zeros(3, dtype=np.int64))
