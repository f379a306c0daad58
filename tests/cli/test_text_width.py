"""Plain text fits the terminal: every line a command prints at 80 columns is at most 100
wide (tables at most 80), long rules folded under their first line, through the real
commands in-process."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from test_bad_figures import GOOD

from tvl_cli.cli.console import TEXT_WIDTH

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "worlds" / "square.txt"
EXAMPLE_LOG = ROOT / "logs" / "square-s1.h5"
TABLE_EDGES = "┏┃┡│└"


# Each test learns, trains, runs or draws: over a second each.
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def fams(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    from conftest import invoke

    folder = tmp_path_factory.mktemp("width")
    made = {
        "single": ("-o", folder / "single.h5"),
        "early": ("-o", folder / "early.h5", "--until-minute", "3"),
        "multi": ("-o", folder / "multi.h5", "--config", "multi"),
    }
    for args in made.values():
        assert invoke("train", EXAMPLE_LOG, *args).returncode == 0
    return {name: args[1] for name, args in made.items()}


def assert_fits(printed: str) -> None:
    for line in printed.splitlines():
        limit = 80 if line[:1] in TABLE_EDGES else TEXT_WIDTH
        assert len(line) <= limit, line


@pytest.mark.parametrize("config", ["single", "multi"])
def test_inspect_folds_each_rule_under_its_first_line(invoke_tvl, fams, config) -> None:
    done = invoke_tvl("inspect", fams[config], "--top", "5")
    assert done.returncode == 0, done.stderr
    assert_fits(done.stdout)
    lines = done.stdout.splitlines()[1:]  # after the method
    starts = [line for line in lines if line.startswith("IF ")]
    assert len(starts) == 5
    # A rule too long for one line goes on under it, indented, and ends with its experience.
    assert all(line.startswith(("IF ", "    ")) for line in lines)
    rules = " ".join(line.strip() for line in lines).split("IF ")[1:]
    assert all(rule.rstrip().endswith(")") and " THEN " in rule for rule in rules)
    found = invoke_tvl("inspect", fams[config], "--top", "5", "--json")
    first = json.loads(found.stdout)["rules"][0]
    assert f"= {first['velocity_mps']:.2f} m/s" in rules[0]


def test_diff_folds_the_rules_that_differ(invoke_tvl, fams) -> None:
    done = invoke_tvl("diff", fams["early"], fams["single"], "--top", "5")
    assert done.returncode == 0, done.stderr
    assert_fits(done.stdout)
    assert done.stdout.count("\nIF ") == 5


@pytest.mark.parametrize("name", sorted(GOOD))
def test_a_figures_summary_fits_the_terminal(invoke_tvl, tmp_path, name) -> None:
    results = tmp_path / "results.jsonl"
    results.write_text("".join(json.dumps(line) + "\n" for line in GOOD[name]))
    table = tmp_path / "table.md"
    done = invoke_tvl("figure", name, results, "-o", tmp_path / "f.png", "--table", table)
    assert done.returncode == 0, done.stderr
    assert_fits(done.stdout)
    # The file keeps the markdown; the terminal shows its titles as titles, its tables as
    # tables, every cell folded whole (no ellipsis) and no markdown left.
    markdown = table.read_text()
    titles = [line[4:] for line in markdown.splitlines() if line.startswith("### ")]
    words = " ".join(done.stdout.split())  # a title folds over a narrow table
    assert all(title in words for title in titles)
    assert done.stdout.count("┏") == len(titles)
    assert "…" not in done.stdout and "|" not in done.stdout and "###" not in done.stdout


def test_every_view_of_a_run_fits(invoke_tvl, fams, tmp_path) -> None:
    trace = tmp_path / "run.h5"
    for args in (
        ("run", fams["single"], SQUARE, "--behaviour", "avoid", "--minutes", "0.3",
         "--log", trace),
        ("replay", trace),
        ("replay", EXAMPLE_LOG),
        ("explain", trace, "--at", "5"),
        ("explain", trace, "--contacts"),
        ("world", "show", SQUARE),
        ("schema",),
    ):  # fmt: skip
        done = invoke_tvl(*args)
        assert done.returncode == 0, (args, done.stderr)
        assert_fits(done.stdout)
