"""`tvl run --learn` and `--learn-log LOG`: learning while behaving, in memory or into a log
`tvl train` replays; its refusals are one line and exit 2."""

from __future__ import annotations

import os
import shutil
import subprocess
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from conftest import TVL
from json_schemas import valid
from method_samples import LIVE_RING
from test_bad_numbers import SQUARE, assert_one_line_refusal

from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.online import OnlineLearner
from tvl_cli.cli import main
from tvl_cli.commands.train import train_from_logs
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.training import SessionEpisodes, TrainParams, train_sessions
from tvl_cli.io.lock import WriterLock
from tvl_cli.io.log_sessions import distinct_sessions
from tvl_cli.io.logfile import LogWriter
from tvl_cli.io.loglayout import KIND_BEHAVING, KIND_LEARNING
from tvl_cli.io.logreader import read_log
from tvl_cli.sim.worldmap import load_world

NARROW = SQUARE.with_name("narrow.txt")
AVOID = ["--behaviour", "avoid", "--minutes", "0.5"]

pytestmark = pytest.mark.slow  # every test here starts a real `tvl` process


@pytest.fixture(scope="module")
def learnt(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """A learning log of one simulated minute in the square, and its FAM."""
    directory = tmp_path_factory.mktemp("learnt")
    log, fam = directory / "log.h5", directory / "fam.h5"
    done = subprocess.run(
        [TVL, "learn", SQUARE, "--log", log, "--minutes", "1", "--fam", fam],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    return log, fam


@pytest.fixture(scope="module")
def learnt_live(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A learning log of one simulated minute in the square through no echo memory."""
    log = tmp_path_factory.mktemp("live") / "log.h5"
    done = subprocess.run(
        [TVL, "learn", SQUARE, "--log", log, "--minutes", "1", "--memory", "none"],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    return log


@pytest.fixture
def fam(learnt: tuple[Path, Path]) -> Path:
    return learnt[1]


def invoke(*args: str | Path) -> tuple[int, str, str]:
    done = CliRunner().invoke(main, ["run", *map(str, args)])
    return done.exit_code, done.stdout, done.stderr


def test_learn_appends_a_behaving_session_that_train_replays(
    learnt: tuple[Path, Path], tmp_path: Path
) -> None:
    log, retrained = tmp_path / "log.h5", tmp_path / "retrained.h5"
    shutil.copy(learnt[0], log)
    fam = learnt[1]
    done = subprocess.run(
        [TVL, "run", fam, SQUARE, *AVOID, "--learn-log", log, "--json"],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    printed = valid("run", done.stdout)
    assert printed["inputs"]["learn"] and printed["outputs"]["log"] == str(log)
    learning = printed["learnt"]
    assert learning["session"] == "0001" and learning["episodes"] > 5
    assert sum(learning["endings"].values()) == learning["episodes"]
    explored, behaved = read_log(log).sessions
    assert (explored.kind, behaved.kind) == (KIND_LEARNING, KIND_BEHAVING)
    assert len(behaved.episode_table) == learning["episodes"]
    assert behaved.exemplar_count == learning["exemplars"]
    assert behaved.parameters["behaviour"] == "avoid" and behaved.status == "finished"
    trained = subprocess.run(
        [TVL, "train", log, "-o", retrained, "--json"], capture_output=True, text=True, timeout=60
    )
    assert trained.returncode == 0, trained.stderr
    assert valid("train", trained.stdout)["exemplars"] == (
        explored.exemplar_count + behaved.exemplar_count
    )


def test_a_behaving_session_trains_every_trajectory_by_heard_labels(
    fam: Path, tmp_path: Path
) -> None:
    # What a behaviour hears labels the ways it did not drive as well (core.heard); the
    # paper's rule labels the driven ones alone.
    log = tmp_path / "behaving.h5"
    done = subprocess.run(
        [TVL, "run", fam, SQUARE, *AVOID, "--learn-log", log],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    (behaved,) = read_log(log).sessions
    driven = {episode.trajectory for episode in behaved.episodes()}
    heard, bumped = (
        train_from_logs([log], SINGLE, replace(DEFAULT, labels=rule)).fam
        for rule in ("heard", "bump")
    )
    names = RobotConfig().trajectories
    # The single FAM's one table: (rules, trajectories) of experience.
    experience = {
        rule: trained.experience_table(0).sum(axis=0)
        for rule, trained in (("heard", heard), ("bump", bumped))
    }
    # Symmetric training gives each driven way's mirror image its exemplars too.
    mirrored = driven | {len(names) - 1 - t for t in driven}
    never = [t for t in range(len(names)) if t not in mirrored]
    assert experience["heard"].sum() > 3 * experience["bump"].sum()
    assert all(experience["bump"][t] == 0 for t in never)
    assert all(experience["heard"][t] > 0 for t in range(len(names)))


def test_the_log_replays_into_the_fam_the_run_ended_with(learnt_live: Path, tmp_path: Path) -> None:
    # A FAM trained on a log goes on learning while behaving into that log: `tvl train` on the
    # log rebuilds the FAM the run ended with, bit for bit. The learner and the log's writer
    # below read the live ring, as the log was learnt.
    log = tmp_path / "log.h5"
    shutil.copy(learnt_live, log)
    robot = RobotConfig()
    world = load_world(SQUARE)
    fam = Fam(SINGLE, [t.name for t in robot.trajectories])
    sessions, _ = distinct_sessions([read_log(log)])
    learnt = [SessionEpisodes(s.episodes(), ended=True) for s in sessions]
    train_sessions(fam, learnt, robot, TrainParams())
    with LogWriter.open(
        log,
        world_name=world.name,
        world_text=world.text,
        seed=1,
        parameters={},
        robot_config=robot.to_dict(),
        fam_config=SINGLE.to_dict(),
        method=LIVE_RING,
        kind=KIND_BEHAVING,
    ) as writer:
        learner = OnlineLearner(fam, robot, TrainParams(), world.start, writer.append_episode)
        live_ring = replace(DEFAULT, memory=NO_MEMORY)
        metrics = behave(
            world, robot, fam, "wall-left", minutes=0.5, seed=3, on_step=learner, method=live_ring
        )
        learner.finish(metrics.sim_s)
    assert learner.summary().episodes > 5
    rebuilt = train_from_logs([log], SINGLE).fam
    np.testing.assert_array_equal(rebuilt.velocity_table(0), fam.velocity_table(0))
    np.testing.assert_array_equal(rebuilt.experience_table(0), fam.experience_table(0))


def test_learn_without_a_log_learns_in_memory_and_writes_no_file(
    fam: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    before = sorted(os.listdir(fam.parent))
    code, out, err = invoke(fam, SQUARE, *AVOID, "--learn", "--json")
    assert code == 0, err
    printed = valid("run", out)
    assert printed["inputs"]["learn"] and printed["outputs"]["log"] is None
    learning = printed["learnt"]
    assert learning["session"] is None and learning["episodes"] > 5
    assert sorted(os.listdir(fam.parent)) == before and not os.listdir(tmp_path)
    code, out, err = invoke(fam, SQUARE, *AVOID, "--learn")
    assert code == 0 and "→ the FAM in memory only" in " ".join(out.split()), err


def test_the_same_seed_writes_the_same_values(fam: Path, tmp_path: Path) -> None:
    logs = [tmp_path / "a.h5", tmp_path / "b.h5"]
    for log in logs:
        code, _, err = invoke(fam, SQUARE, "--behaviour", "wall-right", "--minutes", "0.3",
                              "--seed", "5", "--learn-log", log)  # fmt: skip
        assert code == 0, err
    (a,), (b,) = (read_log(log).sessions for log in logs)
    assert len(a.episode_table) > 3
    np.testing.assert_array_equal(a.episode_table, b.episode_table)
    for column in ("ring_mm", "pose", "odometry", "arc_m", "trajectory", "rotation"):
        np.testing.assert_array_equal(getattr(a, column), getattr(b, column))
    assert a.parameters == b.parameters and a.seed == b.seed == 5


def test_per_minute_contacts_add_up_to_the_run_s(fam: Path) -> None:
    code, out, err = invoke(fam, NARROW, "--behaviour", "wall-right", "--minutes", "1.5",
                            "--paper", "--json")  # fmt: skip
    assert code == 0, err
    printed = valid("run", out)
    assert not printed["inputs"]["learn"] and printed["inputs"]["method"]["reflexes"] == []
    minutes = printed["minutes"]
    assert [m["minute"] for m in minutes] == [1, 2]  # counted from 1, as the tables count
    assert [m["sim_s"] for m in minutes] == pytest.approx([60.0, 30.0])
    assert sum(m["contacts"] for m in minutes) == printed["contacts"] > 0
    assert "learnt" not in printed


def test_bad_logs_are_one_line_and_exit_2(
    learnt: tuple[Path, Path], tmp_path: Path, run_tvl
) -> None:
    fam = learnt[1]
    kept = fam.read_bytes()
    assert_one_line_refusal(
        run_tvl("run", fam, SQUARE, *AVOID, "--learn-log", fam),
        "given as both --learn-log and FAM",
    )
    trace = tmp_path / "trace.h5"
    code, _, err = invoke(fam, SQUARE, *AVOID, "--learn-log", trace, "--log", trace)
    assert code == 2 and "given as both --log and --learn-log" in err
    code, _, err = invoke(fam, SQUARE, *AVOID, "--learn-log", tmp_path / "no" / "log.h5")
    assert code == 2 and "does not exist" in err and err.count("\n") == 1
    world_text = tmp_path / "world.h5"
    shutil.copy(SQUARE, world_text)
    code, _, err = invoke(fam, SQUARE, *AVOID, "--learn-log", world_text)
    assert code == 2 and err.count("\n") == 1 and str(world_text) in err
    assert world_text.read_bytes() == SQUARE.read_bytes()
    locked = tmp_path / "locked.h5"
    shutil.copy(learnt[0], locked)
    held = WriterLock.acquire(locked)
    try:
        code, _, err = invoke(fam, SQUARE, *AVOID, "--learn-log", locked)
    finally:
        held.release()
    assert code == 2 and "locked by another tvl learn or run --learn" in err
    assert len(read_log(locked).sessions) == 1
    assert fam.read_bytes() == kept and not trace.exists()
