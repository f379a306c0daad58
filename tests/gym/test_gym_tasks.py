"""tvl/SonarRing-v0 as an RL user meets it: every configuration passes Gymnasium's checker;
bad actions, goals and options are refused naming themselves; `is_success`; the wall task's
reward; continuous actions; any robot and sonar model; and the vector environment alike."""

from __future__ import annotations

import math
from dataclasses import replace

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from tvl_cli.core.method import DEFAULT
from tvl_cli.core.reward import forward_travel_m
from tvl_cli.core.robot_config import SONAR_MODELS, RobotConfig
from tvl_cli.core.robot_profiles import TURTLEBOT3
from tvl_cli.gym import ENV_ID, SonarRingEnv
from tvl_cli.gym.env import ROBOT, STOP_ACTION
from tvl_cli.gym.task import WALL_DISTANCE_M, WALL_ERROR_WEIGHT

T0 = ROBOT.trajectory_index("T0")
# The square's start, (2.125, 2.125) facing +x: the body's edge 1.425 m from the east wall.
START_CLEARANCE_M = 3.75 - 2.125 - ROBOT.radius_m


def make(**kwargs: object) -> gymnasium.Env:
    return gymnasium.make(ENV_ID, **{"world": "square", **kwargs})


@pytest.mark.slow
@pytest.mark.parametrize("action_type", ["discrete", "continuous", "normalised"])
@pytest.mark.parametrize(
    "kwargs",
    [{"task": "avoid"}, {"task": "goal", "world": "obstacles"}, {"task": "wall"}],
    ids=["avoid", "goal", "wall"],
)
def test_every_configuration_passes_gymnasiums_checker_with_no_display(
    kwargs: dict[str, str], action_type: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    # As on a server or in CI: no display. Any warning fails the test (warnings are errors).
    # The checker renders every mode the environment lists, which here are those it can
    # give; human's window is checked under a display server in test_gym_window.py.
    for name in ("DISPLAY", "WAYLAND_DISPLAY"):
        monkeypatch.delenv(name, raising=False)
    env = make(action_type=action_type, **kwargs)
    assert env.unwrapped.metadata["render_modes"] == ["ansi", "rgb_array"]
    check_env(env.unwrapped)
    env.close()


@pytest.mark.parametrize(
    ("action", "error", "message"),
    [
        (10, ValueError, r"action 10 is not in Discrete\(10\) \(0 to 9\)"),
        (-1, ValueError, r"action -1 is not in Discrete\(10\)"),
        (np.int64(12), ValueError, r"action np.int64\(12\) is not in Discrete\(10\)"),
        (1.5, TypeError, r"action 1.5 is not an int of Discrete\(10\)"),
        (3.0, TypeError, r"action 3.0 is not an int"),
        ("3", TypeError, r"action '3' is not an int"),
        (None, TypeError, r"action None is not an int"),
        (True, TypeError, r"action True is not an int"),
        (np.array([3]), TypeError, r"action array\(\[3\]\) is not an int"),
    ],
)
def test_a_bad_discrete_action_is_refused_naming_it(
    action: object, error: type[Exception], message: str
) -> None:
    env = make()
    env.reset(seed=1)
    with pytest.raises(error, match=message):
        env.step(action)
    # The refused action moved nothing: a good one still steps from the start.
    assert env.step(np.int64(T0))[4]["time_s"] == pytest.approx(0.1)


@pytest.mark.parametrize(
    ("action", "error", "message"),
    [
        ([0.7, 0.0], ValueError, r"action \[0.7, 0.0\] is outside the robot's limits"),
        ([0.0, -1.2], ValueError, r"outside the robot's limits: speed -0.6 to 0.6 m/s, turn -1"),
        ([0.3], ValueError, r"action \[0.3\] is not a finite \(speed m/s, turn rad/s\)"),
        ([math.nan, 0.0], ValueError, r"is not a finite"),
        (3, ValueError, r"action 3 is not a finite"),
        (["a", "b"], TypeError, r"action \['a', 'b'\] is not \(speed m/s, turn rad/s\) in numbers"),
    ],
)
def test_a_bad_continuous_action_is_refused_naming_it(
    action: object, error: type[Exception], message: str
) -> None:
    env = make(action_type="continuous")
    env.reset(seed=1)
    with pytest.raises(error, match=message):
        env.step(action)


def test_continuous_actions_are_any_command_within_the_robots_limits() -> None:
    env = make(action_type="continuous")
    top = max(ROBOT.v_max_mps)
    assert isinstance(env.action_space, gymnasium.spaces.Box)
    np.testing.assert_array_equal(env.action_space.low, [-top, -ROBOT.spin_rate_radps])
    np.testing.assert_array_equal(env.action_space.high, [top, ROBOT.spin_rate_radps])
    assert env.action_space.dtype == np.float64  # a run's commands, given again exactly
    env.reset(seed=1)
    x, y, _ = env.step(np.array([0.3, 0.0]))[4]["pose"]
    assert (x, y) == pytest.approx((2.125 + 0.03, 2.125))
    heading = env.step([0.0, 0.0])[4]["pose"][2]
    assert env.step([-0.2, -0.5])[4]["pose"][2] == pytest.approx(heading - 0.05)
    # A float32 agent's top speed rounds a hair above it: taken as the top speed.
    limits = (top, ROBOT.spin_rate_radps)
    as_float32, as_float64 = make(action_type="continuous"), make(action_type="continuous")
    as_float32.reset(seed=1)
    as_float64.reset(seed=1)
    np.testing.assert_array_equal(
        as_float32.step(np.array(limits, dtype=np.float32))[4]["pose"],
        as_float64.step(np.array(limits))[4]["pose"],
    )
    with pytest.raises(ValueError, match="speed_fraction is for discrete actions only"):
        make(action_type="continuous", speed_fraction=0.5)
    with pytest.raises(ValueError, match="unknown action_type 'box'"):
        make(action_type="box")


@pytest.mark.parametrize(
    ("goal", "error", "message"),
    [
        ((1,), ValueError, r"goal \(1,\) is not a pair \(x, y\) of finite metres"),
        ((1.0, 2.0, 3.0), ValueError, r"goal \(1.0, 2.0, 3.0\) is not a pair"),
        ((1.0, math.inf), ValueError, r"goal \(1.0, inf\) is not a pair \(x, y\) of finite"),
        (("1", "1"), ValueError, r"goal \('1', '1'\) is not a pair"),
        ("1,1", TypeError, r"goal '1,1' is not a pair \(x, y\) of metres"),
        (3.0, TypeError, r"goal 3.0 is not a pair"),
        ({"x": 1}, TypeError, r"goal \{'x': 1\} is not a pair"),
    ],
)
def test_a_bad_goal_is_refused_naming_it(
    goal: object, error: type[Exception], message: str
) -> None:
    with pytest.raises(error, match=message):
        SonarRingEnv("obstacles", task="goal", goal=goal)  # type: ignore[arg-type]


def test_a_goal_may_be_a_list_or_an_array() -> None:
    for goal in ([3.0, 2.125], np.array([3.0, 2.125])):
        assert SonarRingEnv("square", task="goal", goal=goal).goal_xy == (3.0, 2.125)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("options", "error", "message"),
    [
        ([1], TypeError, r"reset options \[1\] are not a dict"),
        ("continue", TypeError, r"reset options 'continue' are not a dict"),
        ({"contine": True}, ValueError, r"reset options \['contine'\] are unknown"),
        ({"continue": "yes"}, TypeError, r"reset option continue='yes' is not True or False"),
    ],
)
def test_bad_reset_options_are_refused_naming_them(
    options: object, error: type[Exception], message: str
) -> None:
    env = make()
    env.reset(seed=1)
    with pytest.raises(error, match=message):
        env.reset(options=options)  # type: ignore[arg-type]


def test_continue_false_and_no_options_start_afresh() -> None:
    env = make()
    first, _ = env.reset(seed=1, options={"continue": False})
    env.step(T0)
    again, info = env.reset(seed=1, options={})
    np.testing.assert_array_equal(first, again)
    assert info["time_s"] == 0.0


def test_is_success_is_true_at_the_step_the_goal_is_reached() -> None:
    env = make(task="goal", goal=(3.0, 2.125))
    _, info = env.reset(seed=1)
    assert info["is_success"] is False
    successes = []
    for _ in range(40):
        _, _, terminated, _, info = env.step(T0)
        successes.append(info["is_success"])
        assert info["is_success"] == info["goal_reached"]
        if terminated:
            break
    # 0.875 m to the goal at 0.06 m a step: reached within 0.3 m on the tenth step, and only
    # that step ends the episode as a success.
    assert successes == [False] * 9 + [True]
    assert "is_success" not in make().reset(seed=1)[1]  # avoiding has no success to report


def test_the_wall_task_rewards_progress_at_the_set_distance_from_a_wall() -> None:
    env = make(task="wall")
    obs, info = env.reset(seed=1)
    assert obs.shape == (16,)
    assert info["clearance_m"] == pytest.approx(START_CLEARANCE_M)
    assert info["wall_error_m"] == pytest.approx(START_CLEARANCE_M - WALL_DISTANCE_M)
    odometry, rewards, clearances = [info["odometry"]], [], []
    for _ in range(40):
        _, reward, terminated, _, info = env.step(T0)  # straight at the east wall
        odometry.append(info["odometry"])
        rewards.append(reward)
        clearances.append(info["clearance_m"])
        if terminated:
            break
    *driving, bumped = rewards
    assert info["bumped"] and info["clearance_m"] == 0.0
    # Each step: metres forward by odometry, less the weighted error from the set distance,
    # less the baseline's penalty at the bump.
    expected = [
        forward_travel_m(tuple(a), tuple(b)) - WALL_ERROR_WEIGHT * abs(c - WALL_DISTANCE_M)
        for a, b, c in zip(odometry[:-1], odometry[1:], clearances, strict=True)
    ]
    assert rewards[:-1] == pytest.approx(expected[:-1])
    assert bumped == pytest.approx(expected[-1] - 6.0)
    # Shaped on the error: the reward rises as the wall nears the set distance, then falls.
    best = int(np.argmax(driving))
    assert abs(clearances[best] - WALL_DISTANCE_M) < 0.06
    assert np.all(np.diff(driving[: best + 1]) > 0) and np.all(np.diff(driving[best:]) < 0)


def test_the_wall_distance_is_checked_and_for_the_wall_task_only() -> None:
    assert (
        SonarRingEnv("square", task="wall", wall_distance_m=0.7).robot_task.wall_distance_m == 0.7
    )
    with pytest.raises(ValueError, match=r"wall_distance_m 0 is outside \(0, 4\) m"):
        SonarRingEnv("square", task="wall", wall_distance_m=0)
    with pytest.raises(ValueError, match=r"wall_distance_m '1' is outside"):
        SonarRingEnv("square", task="wall", wall_distance_m="1")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="wall_distance_m is for task 'wall' only"):
        SonarRingEnv("square", wall_distance_m=0.5)


def test_the_env_takes_any_robot_and_sonar_model() -> None:
    ideal = SonarRingEnv("square", method=replace(DEFAULT, sonar="ideal"))
    assert ideal.robot.sonar == SONAR_MODELS["ideal"]
    a, _ = ideal.reset(seed=1)
    b, _ = ideal.reset(seed=2)
    np.testing.assert_array_equal(a, b)  # no noise: the seed changes nothing of the ring
    small = RobotConfig(radius_m=0.15, spin_rate_radps=0.5)
    env = SonarRingEnv("square", robot=small, method=replace(DEFAULT, sonar="edges"))
    assert env.robot == RobotConfig(radius_m=0.15, spin_rate_radps=0.5, sonar=SONAR_MODELS["edges"])
    env.reset(seed=1)
    assert env.step(STOP_ACTION - 2)[4]["pose"][2] == pytest.approx(0.05)  # spins at 0.5 rad/s
    continuous = SonarRingEnv("square", robot=small, action_type="continuous")
    assert continuous.action_space.high[1] == 0.5
    with pytest.raises(ValueError, match=r"robot big: neither a robot \(yamabico, turtlebot3\)"):
        SonarRingEnv("square", robot="big")
    with pytest.raises(TypeError, match="robot 3 is not a RobotConfig, a robot's name"):
        SonarRingEnv("square", robot=3)  # type: ignore[arg-type]
    assert SonarRingEnv("square", robot="turtlebot3").robot == TURTLEBOT3
    with pytest.raises(TypeError, match="world 3 is not a world's name"):
        SonarRingEnv(3)  # type: ignore[arg-type]


def test_the_ansi_caption_names_a_continuous_command() -> None:
    env = make(action_type="continuous", render_mode="ansi")
    env.reset(seed=1)
    env.step([0.3, -0.5])
    assert env.render().splitlines()[1].startswith("action +0.30 m/s -0.50 rad/s, reward +0.0")


@pytest.mark.parametrize(
    "kwargs",
    [{"task": "wall"}, {"action_type": "continuous"}, {"task": "goal", "world": "obstacles"}],
    ids=["wall", "continuous", "goal"],
)
def test_each_vector_copy_steps_as_a_single_env(kwargs: dict[str, str]) -> None:
    kwargs = {"world": "square", **kwargs}
    ours = gymnasium.make_vec(ENV_ID, num_envs=3, **kwargs)
    theirs = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="sync", **kwargs)
    rng = np.random.default_rng(2)
    steps = [(ours.reset(seed=9), theirs.reset(seed=9))]
    for _ in range(120):
        if kwargs.get("action_type") == "continuous":  # mostly forward, to meet walls
            actions = np.stack([rng.uniform(0.2, 0.6, 3), rng.uniform(-0.5, 0.5, 3)], axis=1)
        else:
            actions = rng.integers(ours.single_action_space.n, size=3)
        steps.append((ours.step(actions), theirs.step(actions)))
    for mine, other in steps:
        for a, b in zip(mine[:-1], other[:-1], strict=True):
            assert a.dtype == b.dtype and a.tobytes() == b.tobytes()
        assert mine[-1].keys() == other[-1].keys()
        for key, value in other[-1].items():
            np.testing.assert_array_equal(mine[-1][key], value, err_msg=key)
    assert any(np.any(mine[2]) for mine, _ in steps[1:])  # episodes ended and were reset


def test_the_vector_env_refuses_bad_actions_and_options() -> None:
    envs = gymnasium.make_vec(ENV_ID, num_envs=2, world="square", action_type="continuous")
    envs.reset(seed=1)
    with pytest.raises(ValueError, match=r"actions of shape \(2,\) for \(2, 2\)"):
        envs.step(np.zeros(2))
    with pytest.raises(ValueError, match=r"is outside the robot's limits"):
        envs.step(np.array([[0.1, 0.0], [0.9, 0.0]]))
    with pytest.raises(TypeError, match=r"reset options \[1\] are not a dict"):
        envs.reset(options=[1])
    with pytest.raises(ValueError, match="a seed starts afresh"):
        envs.reset(seed=1, options={"continue": True})
    fresh = gymnasium.make_vec(ENV_ID, num_envs=2, world="square")
    with pytest.raises(ValueError, match="nothing to continue"):
        fresh.reset(options={"continue": True})
