"""`tvl diff`: where two FAMs disagree, on the command line, run in process."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from conftest import invoke as tvl
from json_schemas import valid

from tvl_cli.io.famfile import read_fam, write_fam

EXAMPLE_LOG = Path(__file__).resolve().parents[2] / "logs" / "square-s1.h5"


@pytest.fixture(scope="module")
def fams(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """FAMs from the example log: after 3 minutes, after all 15, and a multi one."""
    directory = tmp_path_factory.mktemp("diff")
    made = {
        "early": ["--until-minute", "3"],
        "late": [],
        "multi": ["--config", "multi"],
    }
    for name, options in made.items():
        done = tvl("train", EXAMPLE_LOG, "-o", directory / f"{name}.h5", *options)
        assert done.returncode == 0, done.stderr
    return {name: directory / f"{name}.h5" for name in made}


def test_a_fam_agrees_with_itself(fams: dict[str, Path], tmp_path: Path) -> None:
    # The same rules in another file: one file given twice is refused (below).
    late = read_fam(fams["late"])
    again = tmp_path / "again.h5"
    write_fam(
        again,
        late.fam,
        robot_config=late.robot_config,
        method=late.method,
        provenance={**late.provenance, "copied": True},
    )
    printed = valid("diff", tvl("diff", fams["late"], again, "--json").stdout)
    assert printed["differing"] == 0 and printed["rules_differing_most"] == []
    assert {t["mean_abs_change_mps"] for t in printed["trajectories"]} == {0.0}
    assert [printed["inputs"][k]["path"] for k in ("first", "second")] == [
        str(fams["late"]),
        str(again),
    ]


def test_one_fam_given_twice_is_refused_as_train_refuses_one_log_twice(
    fams: dict[str, Path],
) -> None:
    done = tvl("diff", fams["late"], fams["late"])
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert done.stderr.startswith(f"tvl: error: {fams['late']}: the same FAM as ")
    assert "given twice" in done.stderr


@pytest.mark.slow  # over a second: learns, runs or draws at length
def test_more_learning_changes_rules_named_largest_first(fams: dict[str, Path]) -> None:
    done = tvl("diff", fams["early"], fams["late"], "--json", "--top", "0")
    assert done.returncode == 0, done.stderr
    printed = valid("diff", done.stdout)
    named = printed["rules_differing_most"]
    assert printed["differing"] == len(named) > 0
    assert printed["differing"] == sum(t["differing"] for t in printed["trajectories"])
    changes = [abs(rule["change_mps"]) for rule in named]
    assert changes == sorted(changes, reverse=True) and min(changes) > printed["tolerance_mps"]
    early, late = read_fam(fams["early"]).fam, read_fam(fams["late"]).fam
    # The largest change is between the two FAMs' own velocities for that rule.
    (table,) = early.config.tables
    column = table.trajectories.index(named[0]["trajectory"])
    changed = abs(late.velocity_table(0)[:, column] - early.velocity_table(0)[:, column])
    assert max(changed) == pytest.approx(changes[0])
    first, second = named[0]["velocities_mps"]
    assert second - first == pytest.approx(named[0]["change_mps"])


def test_the_words_name_each_trajectory_and_the_rules(fams: dict[str, Path]) -> None:
    done = tvl("diff", fams["early"], fams["late"], "--top", "2")
    assert done.returncode == 0, done.stderr
    assert "T3L" in done.stdout and done.stdout.count(" m/s (experience ") == 2


def test_fams_of_two_configurations_are_refused(fams: dict[str, Path]) -> None:
    done = tvl("diff", fams["late"], fams["multi"])
    assert done.returncode == 2 and done.stderr.count("\n") == 1
    assert "different configurations" in done.stderr


@pytest.mark.slow  # over a second: learns, runs or draws at length
def test_inspect_draws_the_learnt_velocity_over_two_inputs(
    fams: dict[str, Path], tmp_path: Path
) -> None:
    png = tmp_path / "surface.png"
    done = tvl("inspect", fams["late"], "--png", png, "--over", "front,front-right", "--fix",
               "front-left=0.6", "--top", "1")  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert png.read_bytes().startswith(b"\x89PNG")
    bad = tvl("inspect", fams["late"], "--png", tmp_path / "x.png", "--fix", "front-left=near")
    assert bad.returncode == 2 and "'front-left=near' is not INPUT=METRES" in bad.stderr
    assert not (tmp_path / "x.png").exists()


def test_fams_of_different_robots_say_so_in_the_table_and_the_json(
    fams: dict[str, Path], tmp_path: Path
) -> None:
    # The same rules, carried by a robot the size of a TurtleBot3: nothing differs but the
    # robot, and that is what a reader must be told.
    late = read_fam(fams["late"])
    small = tmp_path / "small.h5"
    write_fam(small, late.fam, robot_config=replace(late.robot_config, radius_m=0.105),
              method=late.method, provenance=late.provenance)  # fmt: skip
    shown = tvl("diff", fams["late"], small)
    assert shown.returncode == 0, shown.stderr
    first_line = shown.stdout.splitlines()[0]
    assert first_line.startswith("learnt on different robots (radius_m 0.2 → 0.105)")
    printed = valid("diff", tvl("diff", fams["late"], small, "--json").stdout)
    assert printed["robots_differ_in"] == [{"setting": "radius_m", "first": 0.2, "second": 0.105}]
    assert printed["differing"] == 0


@pytest.mark.slow
def test_fams_learnt_through_different_sonar_models_say_so(
    fams: dict[str, Path], tmp_path: Path
) -> None:
    log, ideal = tmp_path / "ideal.h5", tmp_path / "ideal-fam.h5"
    learnt = tvl("learn", EXAMPLE_LOG.parents[1] / "worlds" / "square.txt", "--log", log,
                 "--minutes", "0.5", "--sonar", "ideal")  # fmt: skip
    assert learnt.returncode == 0, learnt.stderr
    assert tvl("train", log, "-o", ideal).returncode == 0
    printed = valid("diff", tvl("diff", fams["late"], ideal, "--json").stdout)
    assert printed["robots_differ_in"] == [{"setting": "sonar", "first": "real", "second": "ideal"}]
    shown = tvl("diff", fams["late"], ideal).stdout
    assert "learnt on different robots (sonar real → ideal)" in shown


def test_fams_of_one_robot_say_nothing_of_robots(fams: dict[str, Path]) -> None:
    printed = valid("diff", tvl("diff", fams["early"], fams["late"], "--json").stdout)
    assert printed["robots_differ_in"] == []
    assert "different robots" not in tvl("diff", fams["early"], fams["late"]).stdout
