"""`tvl explain`: one moment of a run in the rules of its FAM, through the real process."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import h5py
import pytest
from conftest import TVL
from json_schemas import valid

from tvl_cli.io.famfile import read_fam, write_fam

ROOT = Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.slow  # every test here starts a real `tvl` process


def tvl(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([TVL, *map(str, args)], capture_output=True, text=True, timeout=120)


@pytest.fixture(scope="module")
def collided(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A paper-method run that bumped into something, with the FAM that drove it."""
    directory = tmp_path_factory.mktemp("explain")
    fam = directory / "fam.h5"
    assert tvl("train", ROOT / "logs" / "square-s1.h5", "-o", fam).returncode == 0
    for world in ("circle", "square", "lab"):
        trace = directory / f"{world}.h5"
        args = [fam, ROOT / "worlds" / f"{world}.txt", "--behaviour", "wall-left", "--paper"]
        done = tvl("run", *args, "--minutes", "3", "--log", trace, "--json")
        assert done.returncode == 0, done.stderr
        if valid("run", done.stdout)["collisions"]:
            return {"fam": fam, "trace": trace, "directory": directory}
    raise AssertionError("no paper-method run bumped into anything to explain")


def test_a_collision_is_explained_by_the_rules_that_fired(collided: dict[str, Path]) -> None:
    done = tvl("explain", collided["trace"], "--event", "collision", "--json")
    assert done.returncode == 0, done.stderr
    printed = valid("explain", done.stdout)
    assert printed["inputs"]["fam"]["path"] == str(collided["fam"]) and printed["autopsy"] is None
    assert (printed["inputs"]["event"], printed["inputs"]["index"]) == ("collision", 1)
    moment = printed["step"]
    assert "bump" in moment["events"] and moment["choice"] in moment["focus"]
    why = moment["why"]
    assert why["rules"] and all(rule["strength"] > 0 for rule in why["rules"])
    # The FAM, asked again, perceives what the robot perceived then.
    names = ["T3L", "T2L", "T1L", "T0", "T1R", "T2R", "T3R"]
    for name, velocity in zip(why["trajectories"], why["velocities_mps"], strict=True):
        assert moment["velocities_mps"][names.index(name)] == pytest.approx(velocity, abs=1e-12)
    # replay lists the collision at the time explain gives it, and --at finds it again.
    replayed = valid("replay", tvl("replay", collided["trace"], "--json").stdout)
    bumps = next(e for e in replayed["events"] if e["event"] == "bump")
    assert moment["time_s"] == pytest.approx(bumps["at_s"][0], abs=0.05)
    again = tvl("explain", collided["trace"], "--at", str(bumps["at_s"][0]), "--json")
    assert valid("explain", again.stdout)["step"]["step"] == moment["step"]
    words = tvl("explain", collided["trace"], "--event", "collision")
    assert words.returncode == 0 and "rules that fire" in words.stdout


@pytest.mark.parametrize(
    "moment, message",
    [
        (["--step", "999999"], "--step 999999: the run has steps 0 to"),
        (["--step", "1", "--at", "2"], "give exactly one of --step, --at and --event"),
        (["--at", "-1"], "--at -1: the run lasted"),
        (["--event", "trapped", "--index", "999"], "--index 999: the run has"),
    ],
)
def test_a_moment_the_run_does_not_have_is_one_line(
    collided: dict[str, Path], moment: list[str], message: str
) -> None:
    done = tvl("explain", collided["trace"], *moment)
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and message in done.stderr


def test_a_moved_fam_is_named_and_can_be_given(collided: dict[str, Path]) -> None:
    moved = collided["directory"] / "moved.h5"
    shutil.move(collided["fam"], moved)
    try:
        done = tvl("explain", collided["trace"], "--step", "0")
        assert done.returncode == 2 and "give it with --fam" in done.stderr
        assert tvl("explain", collided["trace"], "--step", "0", "--fam", moved).returncode == 0
    finally:
        shutil.move(moved, collided["fam"])


def _another_fam(collided: dict[str, Path]) -> Path:
    """The run's FAM written again with other provenance: the same rules, another SHA-256."""
    used = read_fam(collided["fam"])
    other = collided["directory"] / "other.h5"
    write_fam(
        other,
        used.fam,
        robot_config=used.robot_config,
        method=used.method,
        provenance={**used.provenance, "copied": True},
    )
    return other


def test_a_fam_the_run_was_not_made_with_is_refused(collided: dict[str, Path]) -> None:
    other = _another_fam(collided)
    done = tvl("explain", collided["trace"], "--step", "0", "--fam", other)
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert done.stderr.startswith(f"tvl: error: {other}: not the FAM {collided['trace']} was run")


def test_a_trace_that_records_no_fam_sha256_takes_the_fam_given(
    collided: dict[str, Path], tmp_path: Path
) -> None:
    trace = tmp_path / "no-sha.h5"
    shutil.copy(collided["trace"], trace)
    with h5py.File(trace, "r+") as f:
        parameters = json.loads(f.attrs["parameters"])
        del parameters["fam_sha256"]
        f.attrs["parameters"] = json.dumps(parameters)
    done = tvl("explain", trace, "--step", "0", "--fam", _another_fam(collided), "--json")
    assert done.returncode == 0, done.stderr
