"""The terminal's tables at 80 columns: units in the headers, values rounded, yes/no and —,
keys in words, and a long path folded whole rather than cut with an ellipsis."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest
from click.testing import CliRunner
from conftest import TVL

from tvl_cli.cli import views
from tvl_cli.cli.main import main
from tvl_cli.cli.tables import cell, label
from tvl_cli.commands.demo import DemoResult, DemoRow
from tvl_cli.commands.learn import LearnRequest, learn_to_log
from tvl_cli.commands.run import RunRequest, run_fam
from tvl_cli.core.learn_params import LearnParams

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "worlds" / "square.txt"
OBSTACLES = ROOT / "worlds" / "obstacles.txt"
EXAMPLE_LOG = ROOT / "logs" / "square-s1.h5"
WIDTH = 80
ELLIPSIS = "…"
# Far longer than any column of an 80-column table.
DEEP = Path(*(f"folder-{i}-of-a-long-path" for i in range(6)))


@pytest.fixture
def eighty_columns(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(views.out, "width", WIDTH)


def tvl(*args: object) -> str:
    done = CliRunner().invoke(main, [str(a) for a in args])
    assert done.exit_code == 0, done.stderr
    return done.stdout


def cells(printed: str, index: int) -> list[str]:
    """The text on each line of a table's column `index` (from 0)."""
    rows = [line.split("│") for line in printed.splitlines() if line.count("│") > 2]
    return [row[index + 1].strip() for row in rows]


def column(printed: str, index: int) -> str:
    """The text of a table's column, its folded lines joined."""
    return "".join(cells(printed, index))


@pytest.fixture(scope="module")
def fam(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A FAM trained from the example log, in a folder of a path longer than a table is wide."""
    trained = tmp_path_factory.mktemp("tables") / DEEP / "single.h5"
    trained.parent.mkdir(parents=True)
    tvl("train", EXAMPLE_LOG, "-o", trained)
    return trained


def assert_fits(printed: str) -> None:
    assert ELLIPSIS not in printed
    assert max(len(line) for line in printed.splitlines()) <= WIDTH


@pytest.mark.parametrize(
    "key, words",
    [
        ("mean_wall_clearance_m", "mean wall clearance (m)"),
        ("mean_speed_mps", "mean speed (m/s)"),
        ("contacts_per_min", "contacts (/min)"),
        ("time_to_goal_s", "time to goal (s)"),
        ("sim_s", "simulated time (s)"),
        ("near_misses", "near misses"),
    ],
)
def test_a_key_reads_as_words_with_its_unit(key: str, words: str) -> None:
    assert label(key) == words


@pytest.mark.parametrize(
    "value, shown",
    [
        (None, "—"),
        (True, "yes"),
        (False, "no"),
        (0.3789561492, "0.38"),
        (6.251405837e-05, "6.25e-05"),
        (0.0, "0.00"),
        (12, "12"),
        (["bump", "tie"], "bump, tie"),
        ([], "—"),
        ({"kind": "patches", "window_s": 20.0}, "kind patches, window (s) 20.00"),
    ],
)
def test_a_value_is_rounded_and_spelt_for_reading(value: object, shown: str) -> None:
    assert cell(value) == shown


def test_run_metrics_read_in_words(eighty_columns: None, fam: Path) -> None:
    printed = tvl("run", fam, SQUARE, "--behaviour", "wall-left", "--minutes", "0.2")
    assert_fits(printed)
    assert "mean wall clearance (m)" in printed
    for raw in ("mean_wall_clearance_m", "True", "False", "None"):
        assert raw not in printed
    # A run that sought no goal says nothing of one.
    assert "goal" not in printed
    # Rounded: no value with more than two decimals.
    values = cells(printed, 1)
    assert len(values) == 14 and not [v for v in values if len(v.partition(".")[2]) > 2]


def test_a_goal_run_says_whether_it_reached_its_goal(eighty_columns: None, fam: Path) -> None:
    printed = tvl("run", fam, OBSTACLES, "--behaviour", "goal", "--minutes", "0.2")
    assert "goal reached" in printed and "time to goal (s)" in printed


def test_the_reflexes_line_says_none_and_no_more(eighty_columns: None, fam: Path) -> None:
    printed = tvl("run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "0.1",
                  "--reflex", "none")  # fmt: skip
    assert "\nreflexes: none\n" in printed
    # The baselines run no reflex by default, and follow no paper.
    printed = tvl("baseline", "dwa", SQUARE, "--minutes", "0.1")
    assert "\nreflexes: none\n" in printed and "paper" not in printed


def test_a_long_fam_path_folds_whole_in_the_replay_table(
    eighty_columns: None, fam: Path, tmp_path: Path
) -> None:
    trace = tmp_path / "run.h5"
    tvl("run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "0.1", "--log", trace)
    printed = tvl("replay", trace)
    assert_fits(printed)
    assert len(str(fam)) > WIDTH and str(fam) in column(printed, 1)


def test_each_table_of_explain_has_its_title_on_one_line(
    eighty_columns: None, fam: Path, tmp_path: Path
) -> None:
    trace = tmp_path / "run.h5"
    tvl("run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "0.1", "--log", trace)
    printed = tvl("explain", trace, "--at", "1.0")
    assert_fits(printed)
    lines = printed.splitlines()
    tops = [i for i, line in enumerate(lines) if line.startswith("┏")]
    assert len(tops) == 3  # inputs, rules that fire, perceived
    for top in tops:
        # Over each table, its title on the line after the text or table before it.
        before = max(i for i, line in enumerate(lines[:top]) if line.startswith(("└", "why")))
        assert top - before == 2, lines[before : top + 1]


def pictures_listed(printed: str) -> list[str]:
    """The paths under the demo's `pictures:` line, one a line."""
    listed = printed.split("\npictures:\n")[1].splitlines()
    assert all(line.startswith("  ") for line in listed)
    return [line.strip() for line in listed]


@pytest.mark.slow
def test_the_demo_names_its_pictures_whole_a_line_each(
    eighty_columns: None, fam: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The demo's table of runs, of a real learning session and real runs."""
    directory = fam.parent
    log = directory / "learn.h5"
    learning = learn_to_log(LearnRequest(SQUARE, log, 1, "single", LearnParams(minutes=0.2)))
    rows = []
    for behaviour in ("avoid", "wall-left"):
        png = directory / f"single-{behaviour}.png"
        metrics = run_fam(RunRequest(fam, SQUARE, behaviour, 0.85, 0.1, 1, png=png))
        rows.append(DemoRow("single", behaviour, 0.85, fam, metrics, png))
    views.demo(DemoResult(directory, learning, rows))
    printed = capsys.readouterr().out
    tables, _, _ = printed.partition("\npictures:\n")
    assert_fits(tables)
    # Longer than the terminal is wide, each path still stands whole on its line.
    assert len(str(rows[0].png)) > WIDTH
    assert pictures_listed(printed) == [str(row.png) for row in rows]


@pytest.mark.slow
def test_the_demo_at_80_columns_names_its_pictures_whole(tmp_path: Path) -> None:
    directory = tmp_path / DEEP
    done = subprocess.run(
        [TVL, "demo", str(directory)],
        capture_output=True,
        text=True,
        timeout=600,
        env={**os.environ, "COLUMNS": str(WIDTH)},
    )
    assert done.returncode == 0, done.stderr
    assert_fits(done.stdout.partition("\npictures:\n")[0])
    assert pictures_listed(done.stdout) == [
        str(directory / f"{config}-{behaviour}.png")
        for config in ("single", "multi")
        for behaviour in ("avoid", "wall-left")
    ]
