"""Every addition to the paper's method is an entry of core.additions.ADDITIONS: its field is a
Method's, the paper's method has it off, ours differs (or the entry says why not), its flag is
on the command line, and the documentation's table is the registry's."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import click
import pytest

from tvl_cli.cli.main import main
from tvl_cli.core.additions import ADDITIONS, Addition, additions_table
from tvl_cli.core.method import (
    DEFAULT,
    ESCAPE,
    FIELDS,
    FLAGS,
    GOAL_WARD,
    PAPER,
    REFLEX_NAMES,
    method_from_dict,
)
from tvl_cli.sweep.grid import read_grid

ROOT = Path(__file__).resolve().parents[1]
# The markers round the generated table (docs/additions_table.py rewrites what is between).
START, END = "<!-- additions:start -->", "<!-- additions:end -->"


def _commands(group: click.Group, ctx: click.Context) -> list[click.Command]:
    found: list[click.Command] = []
    for name in group.list_commands(ctx):
        command = group.get_command(ctx, name)
        assert command is not None
        if isinstance(command, click.Group):
            found += _commands(command, click.Context(command, parent=ctx))
        else:
            found.append(command)
    return found


def _flags(command: click.Command) -> set[str]:
    return {flag for param in command.params for flag in param.opts}


# The benchmark suites name their methods whole (a preset or a method file, one or several),
# their finer choices in a method file: they take no flag of a single field.
SUITES = ("claims", "generalization")
# Every command that takes a method flag by flag, with its options.
WITH_METHOD = [
    _flags(c)
    for c in _commands(main, click.Context(main))
    if "--method" in _flags(c) and c.name not in SUITES
]


def test_the_commands_that_take_a_method_are_those_that_learn_train_design_or_behave() -> None:
    names = sorted(
        c.name or "" for c in _commands(main, click.Context(main)) if "--method" in _flags(c)
    )
    assert names == [
        "claims", "design", "dwa", "generalization", "learn", "qlearn", "run", "train"
    ]  # fmt: skip
    assert all("--paper" in flags for flags in WITH_METHOD)


@pytest.mark.parametrize("addition", ADDITIONS, ids=lambda a: a.name)
def test_an_addition_changes_a_field_the_paper_has_off(addition: Addition) -> None:
    assert addition.field in FIELDS
    assert getattr(PAPER, addition.field) == addition.off
    assert not addition.is_on(PAPER)


@pytest.mark.parametrize("addition", ADDITIONS, ids=lambda a: a.name)
def test_an_addition_is_ours_unless_it_says_why_not(addition: Addition) -> None:
    if addition.not_default:
        # A reflex shares its field with the others: ours leaves that one out.
        if addition.field != "reflexes":
            assert getattr(DEFAULT, addition.field) == getattr(PAPER, addition.field)
        assert not addition.is_on(DEFAULT)
    else:
        assert getattr(DEFAULT, addition.field) != getattr(PAPER, addition.field)
        assert addition.is_on(DEFAULT)


@pytest.mark.parametrize("addition", ADDITIONS, ids=lambda a: a.name)
def test_an_additions_flag_turns_it_on_on_a_command_that_takes_a_method(
    addition: Addition,
) -> None:
    assert FLAGS[addition.field] == addition.flag
    assert any(addition.flag in flags for flags in WITH_METHOD), addition.flag
    # Its setting, as a method file gives it, turns it on over the paper's method.
    value = [addition.on] if addition.field == "reflexes" else addition.on
    given = method_from_dict({addition.field: _typed(addition, value)}, "test")
    assert addition.is_on(replace(PAPER, **{addition.field: getattr(given, addition.field)}))


def _typed(addition: Addition, value: object) -> object:
    numbers = ("decel_mps2", "margin_m", "near_m", "label_ceiling", "label_ceiling_radius_m")
    return float(value) if addition.field in numbers else value


def test_every_difference_from_the_papers_method_is_an_addition() -> None:
    differing = set(DEFAULT.differs(PAPER))
    assert differing <= {a.field for a in ADDITIONS}
    reflexes = {a.on for a in ADDITIONS if a.field == "reflexes"}
    assert reflexes == set(REFLEX_NAMES)


def test_the_documentations_table_is_the_registrys() -> None:
    page = (ROOT / "docs" / "method.md").read_text(encoding="utf-8")
    block = page.split(START)[1].split(END)[0]
    assert block == "\n" + additions_table(), "run python docs/additions_table.py"


def test_the_table_has_a_row_per_addition_naming_its_flag() -> None:
    rows = additions_table().splitlines()[2:]
    assert len(rows) == len(ADDITIONS)
    for addition, row in zip(ADDITIONS, rows, strict=True):
        assert row.startswith(f"| {addition.name} | `{addition.flag} {addition.on}` |")


def test_the_ablation_grid_turns_each_reflex_on_alone_and_runs_the_paper_method() -> None:
    grid = read_grid(ROOT / "experiments" / "grids" / "ablation.toml")
    tvl_runs = [c for c in grid.cells if c.kind == "tvl"]
    settings = {c.reflexes for c in tvl_runs if c.method == "default"}
    # The escape and the goal-ward choice act on goal runs alone, which the grid does not run:
    # their ablations are the generalization benchmark's and the claims' (docs/results.md).
    assert settings >= {"none", "all", *(n for n in REFLEX_NAMES if n not in (ESCAPE, GOAL_WARD))}
    assert any(c.method == "paper" for c in tvl_runs)
