"""One step body: `tvl run` and tvl/SonarRing-v0 step the same engine, so a run's commands
given again to the environment, from the same seed, move, sense and count contacts as the run
did, step for step; and the vector environment, single environments and the drive loop, alone
or over a batch, give the same steps."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner
from method_samples import LIVE_RING
from numpy.random import default_rng

from tvl_cli.agent.drive import Drive, Step, drive_engine, drive_together
from tvl_cli.agent.engine import StepEngine
from tvl_cli.agent.policy import Decision, Observation
from tvl_cli.agent.trace import NOT_READ_MM
from tvl_cli.cli import main
from tvl_cli.commands.train import train_from_logs
from tvl_cli.core.contacts import BUMP, EVENTS, NEAR_MISS, TRAPPED
from tvl_cli.core.drive_command import Command
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.memory import NO_MEMORY, NONE, MemoryChoice
from tvl_cli.core.method import MethodChoice
from tvl_cli.gym import SonarRingEnv, SonarRingVectorEnv
from tvl_cli.gym.env import ROBOT
from tvl_cli.io.famfile import write_fam
from tvl_cli.io.runfile import RunTrace, read_run
from tvl_cli.sim.batch import RobotBatch

ROOT = Path(__file__).resolve().parents[2]
CIRCLE = ROOT / "worlds" / "circle.txt"
# Every event but `trapped`, which is the policy's own verdict and no part of a command.
STEP_EVENTS = sum(1 << i for i, name in enumerate(EVENTS) if name != TRAPPED)
CONTACTS = (1 << EVENTS.index(BUMP)) | (1 << EVENTS.index(NEAR_MISS))


@pytest.fixture(scope="module")
def fam_path(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The single FAM trained from the example log of learning in the square."""
    live_ring = MethodChoice(memory=MemoryChoice(NONE))
    fam = train_from_logs([ROOT / "logs" / "square-s1.h5"], SINGLE, live_ring).fam
    path = tmp_path_factory.mktemp("fam") / "square.h5"
    write_fam(path, fam, robot_config=ROBOT, method=LIVE_RING, provenance={})
    return path


def tvl_run(fam: Path, tmp_path: Path, sonar: str, seed: int, threshold: float) -> RunTrace:
    """`tvl run`, in process, for half a simulated minute of avoiding in the circle."""
    trace = tmp_path / f"{sonar}-{seed}.h5"
    done = CliRunner().invoke(
        main,
        ["run", str(fam), str(CIRCLE), "--behaviour", "avoid", "--minutes", "0.5",
         "--seed", str(seed), "--sonar", sonar, "--threshold", str(threshold),
         "--log", str(trace)],
    )  # fmt: skip
    assert done.exit_code == 0, done.output
    return read_run(trace)


def env_rollout(run: RunTrace, seed: int) -> dict[str, np.ndarray]:
    """The run's commands, one a step, through the environment made with the method the run
    recorded (its sonar model, and the live ring its FAM reads) and reset with its seed."""
    method = run.method
    env = SonarRingEnv(str(CIRCLE), action_type="continuous", method=method)
    assert env.method.memory == NO_MEMORY and env.method.reflexes  # ours, reflexes and all
    obs, _ = env.reset(seed=seed)
    rings, poses, odometry, events = [obs], [], [], []
    commands = np.stack([run.arrays["speed_mps"], run.arrays["turn_radps"]], axis=1)
    for command in commands:
        obs, _, terminated, _, info = env.step(command)
        assert not terminated  # no bump: the run's avoiding kept clear of the wall
        rings.append(obs)
        poses.append(info["pose"])
        odometry.append(info["odometry"])
        events.append(sum(1 << EVENTS.index(e) for e in info["events"]))
    return {
        # The ring before each step, as the trace keeps it: read after the step before.
        "ring_m": np.array(rings[:-1], dtype=np.float64),
        "pose": np.array(poses),
        "odometry": np.array(odometry),
        "events": np.array(events),
    }


def assert_same_readings(run_mm: np.ndarray, env_m: np.ndarray) -> None:
    """The trace keeps whole millimetres, the environment float32 metres: the same reading
    rounds to the same millimetre, where noise drawn apart differs by centimetres."""
    np.testing.assert_allclose(env_m, run_mm / 1000.0, rtol=0, atol=0.0005 + 1e-6)


def test_with_the_ideal_ring_the_env_gives_the_run_step_for_step(
    fam_path: Path, tmp_path: Path
) -> None:
    # The ideal ring draws no noise, so odometry alone draws from the generator: the run and
    # the environment draw alike whichever steps read the ring. A threshold this low drives fast
    # enough to meet the wall: near misses, back-offs and spins.
    run = tvl_run(fam_path, tmp_path, "ideal", seed=3, threshold=0.1)
    ours = env_rollout(run, seed=3)
    arrays = run.arrays
    assert len(ours["pose"]) == run.steps == 300
    np.testing.assert_array_equal(ours["pose"], arrays["pose"])
    np.testing.assert_array_equal(ours["odometry"], arrays["odometry"])
    read = (arrays["ring_mm"] != NOT_READ_MM).all(axis=1)
    assert_same_readings(arrays["ring_mm"][read], ours["ring_m"][read])
    np.testing.assert_array_equal(ours["events"], arrays["events"] & STEP_EVENTS)
    # What was compared holds more than driving on: steps that read nothing (spins, back-offs)
    # and contacts.
    assert (~read).sum() > 10 and (arrays["events"] & CONTACTS).any()
    assert (arrays["speed_mps"] < 0).any() and (arrays["speed_mps"] == 0).any()


def test_with_the_noisy_ring_the_env_gives_the_run_until_the_run_leaves_a_reading(
    fam_path: Path, tmp_path: Path
) -> None:
    run = tvl_run(fam_path, tmp_path, "real", seed=2, threshold=0.85)
    ours = env_rollout(run, seed=2)
    arrays = run.arrays
    # The run reads the ring only when something looks at it; the environment returns it
    # every step. They draw the same noise until the first step the run left unread; after
    # it, odometry and readings draw apart. The true pose is the commands' alone.
    read = (arrays["ring_mm"] != NOT_READ_MM).all(axis=1)
    first_unread = int(np.argmin(read))
    assert not read[first_unread] and first_unread > 20
    same = slice(0, first_unread)
    np.testing.assert_array_equal(ours["pose"], arrays["pose"])
    np.testing.assert_array_equal(ours["odometry"][same], arrays["odometry"][same])
    assert_same_readings(arrays["ring_mm"][same], ours["ring_m"][same])
    np.testing.assert_array_equal(ours["events"][same], arrays["events"][same] & STEP_EVENTS)
    assert not np.array_equal(ours["odometry"], arrays["odometry"])


class Commands:
    """A policy that drives given commands in turn, reading the ring every step as an
    environment returning it does, so that it draws the same sonar noise."""

    def __init__(self, commands: list[Command]) -> None:
        self._commands = iter(commands)

    def decide(self, obs: Observation) -> Decision:
        obs.ring.get()
        return Decision(next(self._commands))

    def interrupt(self) -> None:
        """No plan under way to drop."""


# What one robot's first steps gave, alike for an environment and a drive: the ring before
# each step, in the observation's float32, and the true pose, odometry and events (joined)
# after it.
Seen = dict[str, Any]


def env_seen(observations: list[np.ndarray], infos: list[dict[str, Any]], steps: int) -> Seen:
    """From an environment's observations (the reset's, then each step's) and step infos."""
    return {
        "ring_m": np.array(observations[:steps]),
        "pose": np.array([info["pose"] for info in infos[:steps]]),
        "odometry": np.array([info["odometry"] for info in infos[:steps]]),
        "events": [" ".join(info["events"]) for info in infos[:steps]],
    }


def drive_seen(steps: list[Step], count: int) -> Seen:
    """From a drive's steps."""
    return {
        "ring_m": np.array([step.ring_m for step in steps[:count]], dtype=np.float32),
        "pose": np.array([step.pose for step in steps[:count]]),
        "odometry": np.array([step.odometry for step in steps[:count]]),
        "events": [" ".join(step.events) for step in steps[:count]],
    }


def single_env_seen(env: SonarRingEnv, seed: int, actions: np.ndarray) -> Seen:
    """The episode's steps, to the bump that ends it."""
    observation, _ = env.reset(seed=seed)
    observations, infos = [observation], []
    for action in actions:
        observation, _, terminated, _, info = env.step(int(action))
        observations.append(observation)
        infos.append(info)
        if terminated:
            break
    return env_seen(observations, infos, len(infos))


def vector_env_seen(env: SonarRingVectorEnv, seed: int, actions: np.ndarray) -> list[Seen]:
    """Each copy's first episode, for actions (steps, copies), to the bump that ends it."""
    observation, _ = env.reset(seed=seed)
    observations, infos, ended = [observation], [], []
    for action in actions:
        observation, _, terminated, _, info = env.step(action)
        observations.append(observation)
        infos.append(info)
        ended.append(terminated)
    return [
        env_seen(
            [each[i] for each in observations],
            [{key: value[i] for key, value in info.items()} for info in infos],
            int(np.argmax(np.array(ended)[:, i])) + 1,
        )
        for i in range(env.num_envs)
    ]


@pytest.mark.slow  # about 2 s
def test_vector_env_single_envs_and_run_drives_agree_step_for_step() -> None:
    # The same robots stepped four ways from the same seeds and actions, each until it bumps:
    # by the vector environment (an engine on each robot of one batch), by single environments
    # (a lone engine each), and by the drive loop `tvl run` drives through, alone and together
    # over a batch. The live ring is observed as read, and every way reads it every step.
    copies, seed, steps = 3, 21, 60
    vector = SonarRingVectorEnv(copies, "obstacles", method=LIVE_RING)
    task = vector.robot_task
    # Every copy its own trajectories, into an obstacle within the steps.
    trajectories = len(task.robot.trajectories)
    actions = np.random.default_rng(0).integers(trajectories, size=(steps, copies))
    minutes = steps * task.robot.control_period_s / 60

    def commands(i: int) -> Commands:
        return Commands([task.actions.command(int(a)) for a in actions[:, i]])

    alone: list[list[Step]] = [[] for _ in range(copies)]
    for i in range(copies):
        engine = StepEngine(task.world, task.robot, measure=True)
        engine.reset(seed + i)
        drive_engine(engine, commands(i), minutes, on_step=alone[i].append)
    together: list[list[Step]] = [[] for _ in range(copies)]
    batch = RobotBatch(task.world, task.robot, [default_rng(seed + i) for i in range(copies)])
    drives = [
        Drive(StepEngine.over(batch.alone(i), measure=True), commands(i), minutes, sink.append)
        for i, sink in enumerate(together)
    ]
    drive_together(batch, drives)

    in_vector = vector_env_seen(vector, seed, actions)
    for i in range(copies):
        single = single_env_seen(
            SonarRingEnv("obstacles", method=LIVE_RING), seed + i, actions[:, i]
        )
        count = len(single["pose"])
        assert count > 40 and single["events"][-1] == BUMP  # dozens of steps, then a bump
        ways = {
            "vector env": in_vector[i],
            "drive": drive_seen(alone[i], count),
            "drives together": drive_seen(together[i], count),
        }
        for name, seen in ways.items():
            for key, value in single.items():
                np.testing.assert_array_equal(seen[key], value, err_msg=f"{name}: {key}")
