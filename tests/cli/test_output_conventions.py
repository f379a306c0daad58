"""What the commands print follows one convention each, through the real commands
in-process: CSV a reader takes as it is (true/false, six significant digits, no JSON in a
cell, nothing of a goal a run did not seek); minutes counted from 1 in JSON as in tables;
a log's simulated minutes those it learnt; commands that write a world say so; counts in
the number they take; and progress bars that tell the time left."""

from __future__ import annotations

import csv
import io
import json
import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from tvl_cli.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "worlds" / "square.txt"
OBSTACLES = ROOT / "worlds" / "obstacles.txt"
EXAMPLE_LOG = ROOT / "logs" / "square-s1.h5"
SIX_DIGITS = re.compile(r"-?\d+(\.\d+)?(e[-+]\d+)?")


@pytest.fixture(scope="module")
def fam(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from conftest import invoke

    path = tmp_path_factory.mktemp("conventions") / "single.h5"
    assert invoke("train", EXAMPLE_LOG, "-o", path).returncode == 0
    return path


def rows_of(printed: str) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(printed)))


@pytest.mark.slow  # learns, runs or draws: over a second
def test_a_runs_csv_holds_values_a_reader_takes(invoke_tvl, fam: Path) -> None:
    avoid = invoke_tvl("run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "0.3", "--csv")
    goal = invoke_tvl("run", fam, OBSTACLES, "--behaviour", "goal", "--minutes", "0.3", "--csv")
    (avoiding,), (seeking,) = rows_of(avoid.stdout), rows_of(goal.stdout)
    assert list(avoiding) == list(seeking)  # one header for every behaviour
    assert avoiding["goal_reached"] == avoiding["time_to_goal_s"] == ""  # no goal sought
    assert seeking["goal_reached"] in ("true", "false")
    for row in (avoiding, seeking):
        for key, value in row.items():
            assert value not in ("True", "False", "None") and "[" not in value, key
            if value and value[0].isdigit():
                assert SIX_DIGITS.fullmatch(value), (key, value)
                digits = value.split("e")[0].replace(".", "").replace("-", "").lstrip("0")
                assert len(digits) <= 6, (key, value)


@pytest.mark.slow  # learns, runs or draws: over a second
def test_the_json_and_the_tables_count_minutes_from_1(
    invoke_tvl, fam: Path, tmp_path: Path
) -> None:
    ran = json.loads(
        invoke_tvl("run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "2.5", "--json").stdout
    )
    assert [m["minute"] for m in ran["minutes"]] == [1, 2, 3]
    assert [m["sim_s"] for m in ran["minutes"]] == pytest.approx([60.0, 60.0, 30.0])
    log = tmp_path / "log.h5"
    learnt = json.loads(
        invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "2", "--json").stdout
    )
    assert [m["minute"] for m in learnt["minutes"]] == [1, 2]
    replayed = json.loads(invoke_tvl("replay", log, "--json").stdout)
    assert replayed["minutes"] == learnt["minutes"]
    table = invoke_tvl("learn", SQUARE, "--log", tmp_path / "l2.h5", "--minutes", "2").stdout
    assert [line.split("│")[1].strip() for line in table.splitlines() if "│" in line][:2] == [
        "1",
        "2",
    ]


@pytest.mark.slow  # learns, runs or draws: over a second
def test_a_logs_simulated_minutes_are_those_it_learnt(invoke_tvl, tmp_path: Path) -> None:
    log = tmp_path / "log.h5"
    learnt = json.loads(
        invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "1.5", "--json").stdout
    )
    (session,) = json.loads(invoke_tvl("replay", log, "--json").stdout)["sessions"]
    assert session["sim_minutes"] == learnt["sim_minutes"] == 1.5
    shown = invoke_tvl("replay", log).stdout
    learnt_row = [line for line in shown.splitlines() if line.startswith("│ 0000")][-1]
    assert " 1.5 │" in learnt_row


@pytest.mark.slow  # learns, runs or draws: over a second
def test_world_new_and_render_say_what_they_wrote(invoke_tvl, tmp_path: Path) -> None:
    world, picture = tmp_path / "o.txt", tmp_path / "o.png"
    made = invoke_tvl("world", "new", "obstacles", "-o", world)
    assert made.returncode == 0
    assert made.stdout == f"{world}: a obstacles world (4 segments, 7 discs, 0 rings, 4 goals)\n"
    drawn = invoke_tvl("world", "render", world, "-o", picture)
    assert drawn.stdout == f"{picture}: {world} drawn (4 segments, 7 discs, 0 rings, 4 goals)\n"
    assert picture.read_bytes().startswith(b"\x89PNG")


def test_a_count_of_one_is_singular(invoke_tvl, tmp_path: Path) -> None:
    world = tmp_path / "one.txt"
    world.write_text(
        SQUARE.read_text().replace("version: 1", "version: 1\ndisc: 2.0 1.0 0.2\ngoal: 3 3")
    )
    checked = invoke_tvl("world", "check", world)
    assert checked.returncode == 0, checked.stderr
    assert "1 disc," in checked.stdout and "1 goal)" in checked.stdout
    shown = invoke_tvl("world", "show", world).stdout
    assert "4 segments, 0 rings" in shown


@pytest.mark.slow  # learns or runs for minutes of simulated time
@pytest.mark.parametrize("command", ["learn", "run"])
def test_a_progress_bar_tells_the_time_left(
    fam: Path, tmp_path: Path, command: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    from rich.console import Console

    from tvl_cli.cli import views

    args = {
        "learn": ["learn", SQUARE, "--log", tmp_path / "log.h5", "--minutes", "2"],
        "run": ["run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "4"],
    }[command]
    # A terminal for the bar, as a person running the command has (CliRunner's is none).
    monkeypatch.setattr(views, "err", Console(stderr=True, force_terminal=True, width=120))
    done = CliRunner().invoke(main, [str(a) for a in args])
    assert done.exit_code == 0, done.stderr
    plain = re.sub(r"\x1b\[[0-9;?]*[A-Za-z]", "", done.stderr)
    assert re.search(r"\d+:\d\d:\d\d elapsed, (\d+:\d\d:\d\d|-:--:--) left", plain), plain[-300:]


def test_every_json_document_is_indented_alike(invoke_tvl) -> None:
    """`tvl schema COMMAND`, `tvl schema --json` and a command's --json, one indentation."""
    printed = [
        invoke_tvl("schema", "run").stdout,
        invoke_tvl("schema", "--json").stdout,
        invoke_tvl("world", "check", SQUARE, "--json").stdout,
    ]
    for text in printed:
        second = text.splitlines()[1]
        assert second.startswith(' "') and not second.startswith("  "), second


@pytest.mark.slow  # a minute of a run in the lab
def test_the_events_table_gives_when_each_kind_of_event_began(
    invoke_tvl, fam: Path, tmp_path: Path
) -> None:
    trace = tmp_path / "run.h5"
    lab = ROOT / "worlds" / "lab.txt"
    ran = invoke_tvl("run", fam, lab, "--behaviour", "avoid", "--minutes", "1", "--log", trace)
    assert ran.returncode == 0, ran.stderr
    shown = invoke_tvl("replay", trace).stdout
    events = shown.split("\nevents")[1].split("\nsteps")[0]
    header = [cell.strip() for cell in events.splitlines()[2].split("┃")[1:-1]]
    assert header == ["event", "times", "began at (s)"]
    rows = {
        cells[0]: cells[1:]
        for line in events.splitlines()
        if line.startswith("│")
        for cells in [[cell.strip() for cell in line.split("│")[1:-1]]]
    }
    times, began = rows["spin"]
    assert int(times) > 0 and began != "—"  # spins too say when they began
    for count, when in rows.values():
        assert (int(count) == 0) == (when == "—")
