"""Robots of other sizes through the real commands: `--robot` on world import, learn and run.
A map made here has a pocket behind a gap 0.3 m wide: wide enough for the turtlebot3 profile
(0.21 m across), too narrow for the paper's robot (0.4 m)."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from conftest import invoke
from map_samples import FREE, OCCUPIED, ROS1_FREE_THRESH, UNKNOWN, write_map

from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.robot_profiles import TURTLEBOT3
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.logreader import read_log
from tvl_cli.io.runfile import read_run

# Learning and running take a second or more each.
pytestmark = pytest.mark.slow


def arena_pixels() -> np.ndarray:
    """A 3 x 2.5 m arena at 5 cm whose right 0.75 m is a pocket behind a 0.3 m gap."""
    pixels = np.full((70, 80), UNKNOWN, dtype=np.uint8)
    pixels[10:61, 10:71] = OCCUPIED
    pixels[11:60, 11:70] = FREE
    pixels[11:60, 54] = OCCUPIED  # the pocket's wall
    pixels[30:36, 54] = FREE  # its gap, six cells
    return pixels


@pytest.fixture(scope="module")
def made(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The map imported for the turtlebot3, learnt in by it for 3 minutes, and trained."""
    where = tmp_path_factory.mktemp("robots")
    files = {name: where / name for name in ("arena.txt", "log.h5", "fam.h5")}
    files["map"] = write_map(where, arena_pixels(), ROS1_FREE_THRESH, name="arena")
    for args in (
        ("world", "import", files["map"], "-o", files["arena.txt"], "--robot", "turtlebot3"),
        ("learn", files["arena.txt"], "--log", files["log.h5"], "--minutes", "3", "--robot",
         "turtlebot3"),
        ("train", files["log.h5"], "-o", files["fam.h5"]),
    ):  # fmt: skip
        done = invoke(*args)
        assert done.returncode == 0, (args, done.stderr)
        assert done.stderr == ""  # the turtlebot3 fits through the gap: no warning
    return files


def test_the_import_judges_passages_for_the_robot_named(made, tmp_path: Path) -> None:
    done = invoke("world", "import", made["map"], "-o", tmp_path / "big.txt", "--json")
    assert done.returncode == 0, done.stderr
    passages = json.loads(done.stdout)["narrow_passages"]
    assert len(passages) == 1 and passages[0]["width_m"] == pytest.approx(0.3, abs=0.05)
    assert "narrower than the robot (0.4 m across)" in done.stderr


def test_the_log_and_the_fam_record_the_robot_that_learnt(made) -> None:
    log = read_log(made["log.h5"])
    assert {s.robot_config for s in log.sessions} == {TURTLEBOT3}
    assert read_fam(made["fam.h5"]).robot_config == TURTLEBOT3
    inspected = invoke("inspect", made["fam.h5"], "--top", "1")
    assert inspected.stdout.splitlines()[:2] == ["method: default", "robot: turtlebot3"]


def test_a_fam_drives_its_own_robot_and_refuses_another(made, tmp_path: Path) -> None:
    run = ("run", made["fam.h5"], made["arena.txt"], "--behaviour", "avoid", "--minutes", "0.5")
    refused = invoke(*run, "--robot", "yamabico")
    assert refused.returncode == 2
    assert refused.stderr.startswith(
        f"tvl: error: {made['fam.h5']}: FAM was learnt on the turtlebot3 robot, not on the "
        "yamabico robot (radius_m 0.105 → 0.2; "
    )
    assert refused.stderr.endswith("; learn one with that --robot\n")
    assert len(refused.stderr.splitlines()) == 1
    trace = tmp_path / "run.h5"
    done = invoke(*run, "--robot", "turtlebot3", "--log", trace, "--json")
    assert done.returncode == 0, done.stderr
    assert RobotConfig.from_dict(read_run(trace).robot_config) == TURTLEBOT3
    # No faster than the small robot can drive.
    poses = read_run(trace).arrays["pose"]
    steps = np.hypot(*np.diff(poses[:, :2], axis=0).T)
    assert steps.max() <= max(TURTLEBOT3.v_max_mps) * 0.1 * 1.05
    assert json.loads(done.stdout)["distance_m"] > 1.0
    assert json.loads(done.stdout)["inputs"]["robot"] == "turtlebot3"


def test_a_robot_file_learns_and_one_log_keeps_one_robot(made, tmp_path: Path) -> None:
    robot_file = tmp_path / "wider.toml"
    robot_file.write_text('base = "turtlebot3"\nradius_m = 0.12\n', encoding="utf-8")
    log = tmp_path / "log.h5"
    learnt = ("learn", made["arena.txt"], "--log", log, "--minutes", "0.5")
    done = invoke(*learnt, "--robot", robot_file, "--json")
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["inputs"]["robot"] is None  # a robot of its own
    assert read_log(log).sessions[0].robot_config == replace(TURTLEBOT3, radius_m=0.12)
    other = invoke(*learnt, "--robot", "turtlebot3")
    assert other.returncode == 2
    assert other.stderr == (
        f"tvl: error: {log}: session 0000 was recorded with another robot configuration; "
        "log this robot to a new file\n"
    )


def test_a_faulty_robot_file_is_one_line(made, tmp_path: Path) -> None:
    robot_file = tmp_path / "bad.toml"
    robot_file.write_text("radius_m = -1\n", encoding="utf-8")
    done = invoke("learn", made["arena.txt"], "--log", tmp_path / "log.h5", "--robot", robot_file)
    assert done.returncode == 2
    assert len(done.stderr.splitlines()) == 1
    assert f"{robot_file}: radius_m -1 must be 0.03 or more and at most 1 m" in done.stderr
    assert not (tmp_path / "log.h5").exists()


def test_learning_goes_on_from_a_fam_of_its_own_robot_only(made, tmp_path: Path) -> None:
    learnt = ("learn", made["arena.txt"], "--minutes", "0.2", "--from-fam", made["fam.h5"])
    other = invoke(*learnt, "--log", tmp_path / "a.h5")
    assert other.returncode == 2
    assert other.stderr == (
        f"tvl: error: {made['fam.h5']}: FAM was learnt on the turtlebot3 robot, not on the "
        "yamabico robot; give --robot to match it\n"
    )
    heard = invoke(*learnt, "--log", tmp_path / "b.h5", "--robot", "turtlebot3", "--sonar", "ideal")
    assert heard.returncode == 2
    assert heard.stderr == (
        f"tvl: error: {made['fam.h5']}: FAM was learnt hearing by the real sonar model, not the "
        "ideal; give --sonar to match it\n"
    )
    same = invoke(*learnt, "--log", tmp_path / "c.h5", "--robot", "turtlebot3")
    assert same.returncode == 0, same.stderr


def test_an_untrained_entry_reads_slower_than_the_robots_slowest_trajectory(
    made, tmp_path: Path
) -> None:
    # 0.2 m/s is below the paper's robot's slowest top speed (0.35), not the turtlebot3's (0.15).
    refusal = (
        "--init-velocity 0.2 must be below the slowest trajectory's maximum of the turtlebot3 "
        "robot (0.15 m/s)"
    )
    learnt = invoke("learn", made["arena.txt"], "--log", tmp_path / "log.h5", "--robot",
                    "turtlebot3", "--init-velocity", "0.2")  # fmt: skip
    assert (learnt.returncode, learnt.stderr) == (2, f"tvl: error: {refusal}\n")
    assert not (tmp_path / "log.h5").exists()
    trained = invoke("train", made["log.h5"], "-o", tmp_path / "f.h5", "--init-velocity", "0.2")
    assert (trained.returncode, trained.stderr) == (2, f"tvl: error: {refusal}\n")
    kept = invoke("train", made["log.h5"], "-o", tmp_path / "f.h5", "--init-velocity", "0.1")
    assert kept.returncode == 0, kept.stderr
