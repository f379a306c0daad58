"""The learn -> train -> inspect -> run -> replay pipeline on the command line, run in process;
two tests start the real `tvl` process, for an output kept and a seed repeated."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest
from conftest import invoke
from hdf5_contents import datasets
from json_schemas import ENVELOPE, valid

from tvl_cli.core.robot_config import EDGE_ECHO_RANGE_M, RobotConfig
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.logreader import read_log
from tvl_cli.sim.worldmap import load_world

WORLDS = Path(__file__).resolve().parents[2] / "worlds"
SQUARE = WORLDS / "square.txt"


@pytest.fixture(scope="module")
def learnt(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """One short learning session with its online FAM, shared by the tests of this module."""
    directory = tmp_path_factory.mktemp("learnt")
    log, online = directory / "log.h5", directory / "online.h5"
    learning = invoke("learn", SQUARE, "--log", log, "--minutes", "2", "--fam", online)
    assert learning.returncode == 0, learning.stderr
    return {"log": log, "online": online, "dir": directory}


@pytest.mark.slow
def test_train_rebuilds_the_online_fam_exactly(invoke_tvl, learnt, tmp_path):
    rebuilt = tmp_path / "rebuilt.h5"
    result = invoke_tvl("train", learnt["log"], "-o", rebuilt)
    assert result.returncode == 0, result.stderr
    online, again = read_fam(learnt["online"]).fam, read_fam(rebuilt).fam
    for t in range(len(online.config.tables)):
        assert np.array_equal(online.velocity_table(t), again.velocity_table(t))
        assert np.array_equal(online.experience_table(t), again.experience_table(t))


@pytest.mark.slow  # over a second: learns, runs or draws at length
def test_training_twice_gives_byte_identicaldatasets(invoke_tvl, learnt, tmp_path):
    first, second = tmp_path / "a.h5", tmp_path / "b.h5"
    assert invoke_tvl("train", learnt["log"], "-o", first, "--config", "multi").returncode == 0
    assert invoke_tvl("train", learnt["log"], "-o", second, "--config", "multi").returncode == 0
    assert datasets(first) == datasets(second)
    assert datasets(first)  # there is something to compare


@pytest.mark.slow
def test_train_summary_counts_exemplars_and_rules(invoke_tvl, learnt, tmp_path):
    result = invoke_tvl("train", learnt["log"], "-o", tmp_path / "f.h5")
    exemplars = read_log(learnt["log"]).exemplar_count
    assert f"{exemplars}" in result.stdout
    assert "of 720" in result.stdout


def test_train_refuses_an_existing_output_without_force(run_tvl, learnt, tmp_path):
    output = tmp_path / "keep.h5"
    output.write_bytes(b"precious")
    result = run_tvl("train", learnt["log"], "-o", output)
    assert result.returncode == 2
    assert "already exists" in result.stderr
    assert output.read_bytes() == b"precious"
    assert run_tvl("train", learnt["log"], "-o", output, "--force").returncode == 0


def test_inspect_prints_readable_rules(invoke_tvl, learnt):
    result = invoke_tvl("inspect", learnt["online"], "--trajectory", "T1L", "--top", "3")
    method, *lines = result.stdout.strip().splitlines()
    # Each rule a sentence, folded at the terminal's width under its first line.
    rules = " ".join(line.strip() for line in lines).split("IF ")[1:]
    assert result.returncode == 0 and len(rules) == 3
    assert method == "method: default"  # the method the FAM was made by comes first
    for rule in rules:
        assert rule.startswith("front is ")
        assert " THEN T1L = " in rule and "m/s" in rule and "(experience " in rule


def test_inspect_json_lists_rules_with_their_conditions(invoke_tvl, learnt):
    result = invoke_tvl("inspect", learnt["online"], "--json", "--top", "5", "--sort", "velocity")
    data = valid("inspect", result.stdout)
    assert data["explanation"] is None and data["inputs"]["sort"] == "velocity"
    assert data["method"]["preset"] == "default"
    velocities = [rule["velocity_mps"] for rule in data["rules"]]
    assert velocities == sorted(velocities, reverse=True) and len(velocities) == 5
    assert [c["input"] for c in data["rules"][0]["conditions"]] == [
        "front",
        "front-left",
        "rear-left",
        "rear-right",
        "front-right",
    ]
    assert data["provenance"]["logs"][0]["sha256"]


def test_inspect_untrained_lists_only_rules_without_experience(invoke_tvl, learnt):
    data = valid("inspect", invoke_tvl("inspect", learnt["online"], "--untrained", "--json").stdout)
    assert data["rules"]
    assert all(rule["experience"] == 0 and rule["velocity_mps"] == 0.1 for rule in data["rules"])


def test_inspect_explain_shows_fired_rules_and_velocities(invoke_tvl, learnt):
    ring = ",".join(["0.5"] + ["2.0"] * 15)
    printed = valid(
        "inspect", invoke_tvl("inspect", learnt["online"], "--explain", ring, "--json").stdout
    )
    assert printed["rules"] is None and printed["inputs"]["explain_ring_m"][:2] == [0.5, 2.0]
    data = printed["explanation"]
    assert len(data["velocities_mps"]) == 7 and len(data["experience"]) == 7
    assert data["rules"], "at least one rule fires for any ring"
    front = next(i for i in data["inputs"] if i["name"] == "front")
    assert front["value_m"] == 0.5
    assert abs(sum(s["degree"] for s in front["fired"]) - 1.0) < 1e-12


def test_inspect_refuses_an_unknown_trajectory(invoke_tvl, learnt):
    result = invoke_tvl("inspect", learnt["online"], "--trajectory", "T9X")
    assert result.returncode == 2
    assert "unknown trajectory 'T9X'" in result.stderr


@pytest.mark.slow  # over a second: learns, runs or draws at length
def test_run_prints_the_metrics_json(invoke_tvl, learnt, tmp_path):
    trace, png = tmp_path / "run.h5", tmp_path / "run.png"
    result = invoke_tvl(
        "run", learnt["online"], SQUARE, "--behaviour", "wall-left", "--minutes", "0.5",
        "--json", "--log", trace, "--png", png,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    metrics = valid("run", result.stdout)
    assert metrics["outputs"] == {"png": str(png), "trace": str(trace), "log": None}
    assert metrics["status"] == "finished"
    assert set(metrics) - ENVELOPE - {"status"} == {
        "sim_s", "distance_m", "mean_speed_mps", "mean_drive_speed_mps", "collisions",
        "near_misses", "contacts", "contacts_per_min", "collisions_per_min", "backoffs",
        "spins", "trapped", "mean_clearance_m", "mean_wall_clearance_m", "goal_reached",
        "time_to_goal_s", "minutes",
    }  # fmt: skip
    assert metrics["inputs"]["method"]["preset"] == "default"
    assert metrics["contacts"] == metrics["collisions"] + metrics["near_misses"]
    assert metrics["sim_s"] == pytest.approx(30.0)
    assert png.stat().st_size > 1000
    replayed = valid("replay", invoke_tvl("replay", trace, "--json").stdout)
    assert replayed["format"] == "tvl-run" and replayed["steps"] == 300
    assert replayed["parameters"]["minutes"] == 0.5  # the run's length, as asked for
    assert replayed["parameters"]["fam"] == metrics["inputs"]["fam"]
    assert replayed["metrics"] == {k: metrics[k] for k in replayed["metrics"]}
    with h5py.File(trace) as f:
        driven = f["trajectory"][()]
    names = [t.name for t in RobotConfig().trajectories]
    assert [t["trajectory"] for t in replayed["trajectories"]] == names
    per_trajectory = [t["steps"] for t in replayed["trajectories"]]
    assert per_trajectory == [int((driven == j).sum()) for j in range(len(names))]
    assert 0 < sum(per_trajectory) <= 300


@pytest.mark.parametrize("method", [["--paper"], ["--reflex", "none"]])
def test_the_paper_method_runs_alone_and_says_so(invoke_tvl, learnt, tmp_path, method):
    trace = tmp_path / "run.h5"
    args = ["run", learnt["online"], SQUARE, "--behaviour", "avoid", "--minutes", "0.2"]
    result = invoke_tvl(*args, *method, "--log", trace, "--json")
    assert result.returncode == 0, result.stderr
    metrics = valid("run", result.stdout)
    assert metrics["contacts"] == metrics["collisions"] + metrics["near_misses"]
    assert metrics["inputs"]["method"]["reflexes"] == []
    replayed = valid("replay", invoke_tvl("replay", trace, "--json").stdout)
    assert replayed["method"]["reflexes"] == replayed["reflexes"] == []
    with h5py.File(trace) as f:
        assert (f["reflex"][()] == -1).all()  # no step was taken by a reflex


def test_reflexes_are_named_in_the_trace_and_the_table(invoke_tvl, learnt, tmp_path):
    trace = tmp_path / "run.h5"
    args = ["run", learnt["online"], SQUARE, "--behaviour", "avoid", "--minutes", "0.2"]
    result = invoke_tvl(*args, "--reflex", "bump,near-miss", "--log", trace)
    assert result.returncode == 0, result.stderr
    assert "reflexes: near-miss, bump" in result.stdout
    replayed = valid("replay", invoke_tvl("replay", trace, "--json").stdout)
    assert replayed["method"]["reflexes"] == ["near-miss", "bump"]
    assert [r["reflex"] for r in replayed["reflexes"]] == ["near-miss", "bump"]


def test_paper_and_reflex_together_are_refused(invoke_tvl, learnt):
    args = ["run", learnt["online"], SQUARE, "--behaviour", "avoid", "--paper"]
    result = invoke_tvl(*args, "--reflex", "bump")
    assert result.returncode == 2
    assert (
        result.stderr.strip() == "tvl: error: --reflex cannot be given with --paper, which fixes it"
    )


def test_an_unknown_reflex_is_refused_by_name(invoke_tvl, learnt):
    args = ["run", learnt["online"], SQUARE, "--behaviour", "avoid", "--reflex", "bump,typo"]
    result = invoke_tvl(*args)
    assert result.returncode == 2 and "unknown reflex typo" in result.stderr


@pytest.mark.slow
def test_an_ideal_sonar_fam_runs_with_the_ideal_sonar(invoke_tvl, tmp_path):
    log, fam, trace = tmp_path / "log.h5", tmp_path / "fam.h5", tmp_path / "run.h5"
    learn = invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "1", "--sonar", "ideal")
    assert learn.returncode == 0, learn.stderr
    assert invoke_tvl("train", log, "-o", fam).returncode == 0
    args = ["run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "0.2", "--log", trace]
    result = invoke_tvl(*args)
    assert result.returncode == 0, result.stderr
    replayed = valid("replay", invoke_tvl("replay", trace, "--json").stdout)
    assert replayed["method"]["sonar"] == "ideal"
    real = invoke_tvl(*args[:-2], "--sonar", "real", "--log", tmp_path / "real.h5")
    assert real.returncode == 0, real.stderr


@pytest.mark.slow  # over a second
def test_an_edges_sonar_fam_runs_with_edge_echoes_and_keeps_them_in_its_robot(invoke_tvl, tmp_path):
    log, fam = tmp_path / "log.h5", tmp_path / "fam.h5"
    learn = invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "1", "--sonar", "edges")
    assert learn.returncode == 0, learn.stderr
    assert invoke_tvl("train", log, "-o", fam).returncode == 0
    assert read_fam(fam).robot_config.sonar.edge_echo_range_m == EDGE_ECHO_RANGE_M
    for sonar, expected in ((None, "edges"), ("ideal", "ideal")):
        trace = tmp_path / f"{expected}.h5"
        args = ["run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "0.2", "--log", trace]
        ran = invoke_tvl(*args, *(["--sonar", sonar] if sonar else []))
        assert ran.returncode == 0, ran.stderr
        replayed = valid("replay", invoke_tvl("replay", trace, "--json").stdout)
        assert replayed["method"]["sonar"] == expected


def test_same_seed_gives_identical_logs_and_run_json(run_tvl, tmp_path):
    outputs = []
    for name in ("a", "b"):
        log, fam = tmp_path / f"{name}.h5", tmp_path / f"{name}-fam.h5"
        run_tvl("learn", SQUARE, "--log", log, "--minutes", "1", "--seed", "7", "--fam", fam)
        run = run_tvl("run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "0.5", "--json")
        # What the run found: its inputs name each its own FAM file.
        found = {k: v for k, v in valid("run", run.stdout).items() if k != "inputs"}
        outputs.append((datasets(log), found))
    assert outputs[0] == outputs[1]
    other = tmp_path / "other.h5"
    run_tvl("learn", SQUARE, "--log", other, "--minutes", "1", "--seed", "8")
    assert datasets(other) != outputs[0][0]


def test_learn_json_summary(invoke_tvl, tmp_path):
    result = invoke_tvl("learn", SQUARE, "--log", tmp_path / "l.h5", "--minutes", "1", "--json")
    summary = valid("learn", result.stdout)
    assert summary["inputs"]["minutes"] == 1.0 and summary["outputs"]["log"] == str(
        tmp_path / "l.h5"
    )
    # Learning stops at the first control step past the minute, or after the last back-off.
    assert 1.0 <= summary["sim_minutes"] <= 1.0 + 2.0 / 60 and summary["exemplars"] > 0
    assert summary["exemplars"] == read_log(tmp_path / "l.h5").exemplar_count


@pytest.mark.slow
def test_learning_again_on_a_log_adds_a_session(invoke_tvl, tmp_path):
    log = tmp_path / "l.h5"
    for seed in ("1", "2"):
        assert (
            invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "0.5", "--seed", seed).returncode
            == 0
        )
    assert [s.seed for s in read_log(log).sessions] == [1, 2]


@pytest.mark.slow  # over a second
def test_replay_of_a_learning_log_draws_paths_and_curves(invoke_tvl, learnt, tmp_path):
    png, curves = tmp_path / "paths.png", tmp_path / "curves.png"
    result = invoke_tvl("replay", learnt["log"], "--png", png, "--curves", curves, "--json")
    data = valid("replay", result.stdout)
    assert data["format"] == "tvl-log" and len(data["minutes"]) == 2
    assert png.stat().st_size > 1000 and curves.stat().st_size > 1000


@pytest.mark.slow  # over a second: learns, runs or draws at length
def test_demo_runs_to_the_end(invoke_tvl, tmp_path):
    result = invoke_tvl("demo", tmp_path / "demo")
    assert result.returncode == 0, result.stderr
    for name in ("learn.h5", "single.h5", "multi.h5", "single-avoid.png", "multi-wall-left.png"):
        assert (tmp_path / "demo" / name).stat().st_size > 0
    assert "behaviours after learning" in result.stdout


def test_demo_refuses_a_directory_in_use(invoke_tvl, tmp_path):
    (tmp_path / "mine.txt").write_text("keep")
    result = invoke_tvl("demo", tmp_path)
    assert result.returncode == 2 and "not empty" in result.stderr
    assert (tmp_path / "mine.txt").read_text() == "keep"


def test_world_of_the_log_travels_with_it(learnt, tmp_path):
    # A log copied elsewhere still knows its world: replay needs no world file.
    moved = tmp_path / "moved.h5"
    shutil.copyfile(learnt["log"], moved)
    assert read_log(moved).sessions[0].world_text == SQUARE.read_text(encoding="utf-8")


@pytest.mark.slow
def test_train_until_a_minute_uses_only_the_episodes_finished_by_then(invoke_tvl, learnt, tmp_path):
    snapshot, whole = tmp_path / "snapshot.h5", tmp_path / "whole.h5"
    assert invoke_tvl("train", learnt["log"], "-o", snapshot, "--until-minute", "1").returncode == 0
    assert invoke_tvl("train", learnt["log"], "-o", whole).returncode == 0
    (session,) = read_log(learnt["log"]).sessions
    early = int(session.episode_table["count"][session.episode_table["end_time_s"] <= 60].sum())
    assert 0 < early < session.exemplar_count
    experience = [read_fam(p).fam.experience_table(0).sum() for p in (snapshot, whole)]
    assert 0 < experience[0] < experience[1]
    assert read_fam(snapshot).provenance["until_minute"] == 1.0


def test_every_episode_is_counted_in_a_recorded_minute(invoke_tvl, tmp_path):
    log = tmp_path / "l.h5"
    # In the corridor with bumps only, seed 1 ends an episode on the closing boundary.
    summary = invoke_tvl(
        "learn", WORLDS / "corridor.txt", "--log", log, "--minutes", "1", "--near", "0", "--json"
    )
    replayed = valid("replay", invoke_tvl("replay", log, "--json").stdout)
    episodes = sum(row["episodes"] for row in replayed["minutes"])
    assert episodes == valid("learn", summary.stdout)["episodes"]


@pytest.mark.slow  # over a second: learns, runs or draws at length
def test_a_trace_longer_than_a_chunk_holds_every_step_once(invoke_tvl, learnt, tmp_path):
    """A trace is written a chunk of steps at a time: the joins lose and repeat nothing."""
    trace = tmp_path / "run.h5"
    args = ["run", learnt["online"], SQUARE, "--behaviour", "avoid", "--minutes", "2.5"]
    result = invoke_tvl(*args, "--log", trace, "--json")
    assert result.returncode == 0, result.stderr
    metrics = json.loads(result.stdout)
    with h5py.File(trace) as f:
        assert f["pose"].chunks[0] < len(f["pose"]) == 1500  # more than one chunk
        assert {len(f[name]) for name in f} == {1500}
        xy = f["pose"][:, :2]
    # The run's distance counts its first step's move too, from the start the trace leaves out.
    path = np.vstack([load_world(SQUARE).start[:2], xy])
    assert np.hypot(*np.diff(path, axis=0).T).sum() == pytest.approx(
        metrics["distance_m"], abs=1e-3
    )
