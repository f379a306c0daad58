"""`tvl design`: FAM inputs chosen from learning logs."""

from __future__ import annotations

from pathlib import Path

import click

from tvl_cli.analysis.input_selection import DEFAULT_BUDGET_RULES
from tvl_cli.cli.examples import examples
from tvl_cli.cli.fam_views import trained_method
from tvl_cli.cli.memory_options import memory_options
from tvl_cli.cli.options import (
    JSON_FILE,
    SEED,
    label_options,
    method_options,
    print_json,
    refuse_outputs,
)
from tvl_cli.cli.tables import table
from tvl_cli.cli.views import out
from tvl_cli.commands.design import DesignSummary, design_from_logs
from tvl_cli.core.fam_config_json import MAX_ENTRIES
from tvl_cli.core.method import MethodChoice
from tvl_cli.core.words import counted


@click.command(epilog=examples("design"))
@click.argument("logs", nargs=-1, required=True, type=click.Path(path_type=Path))
@click.option("-o", "--output", type=JSON_FILE, required=True, help="CONFIG.json to write.")
@click.option(
    "--budget",
    type=click.IntRange(1, MAX_ENTRIES),
    default=DEFAULT_BUDGET_RULES,
    show_default=True,
    metavar="RULES",
    help="Most rules of all tables together (default: the multi FAM's).",
)
@click.option(
    "--seed",
    type=SEED,
    default=1,
    show_default=True,
    help="Seed of the split into training and held-out episodes.",
)
@method_options
@label_options
@memory_options(base="the one the logs were learnt through")
@click.option("--force", is_flag=True, help="Overwrite OUTPUT.")
@click.option("--json", "as_json", is_flag=True, help="Print a JSON summary.")
def design(
    logs: tuple[Path, ...],
    output: Path,
    budget: int,
    seed: int,
    method: MethodChoice,
    force: bool,
    as_json: bool,
) -> None:
    """Choose each FAM table's sonars and fuzzy sets from learning logs.

    For the straight trajectory's table and each left one (the right ones mirror them), adds
    one input at a time, a sonar or the nearest of 2 or 3 adjacent ones with 2 to 5 fuzzy
    sets, whichever, trained on three quarters of the episodes, best perceives the velocity
    labels of the rest; until the rules would exceed the budget or no input lowers that
    error measurably. The episodes are read and labelled as `tvl train` with the same method
    reads and labels them. Writes a configuration for `tvl train --config CONFIG.json` that
    records each choice's held-out error before and after.
    """
    refuse_outputs({"-o": output}, {f"LOG {i + 1}": log for i, log in enumerate(logs)}, force)
    summary = design_from_logs(list(logs), output, budget, seed, force, method)
    if as_json:
        print_json(summary.document())
    else:
        _show(summary, method)


def _show(summary: DesignSummary, choice: MethodChoice) -> None:
    config = summary.design.config
    assert config.design is not None
    choices = table(
        "table", "added", "held-out error (m/s)", title=f"inputs chosen → {summary.output}"
    )
    for c in config.design.choices:
        before, after = c.heldout_error_before_mps, c.heldout_error_after_mps
        choices.add_row(c.table, ", ".join(c.inputs), f"{before:.3f} → {after:.3f}")
    out.print(choices)
    tables = table(
        "table",
        "inputs (fuzzy sets)",
        "rules",
        title=f"{config.name}: {config.rule_count:,} rules",
        right=("rules",),
    )
    for t in config.tables:
        sets = ", ".join(f"{i.name} ({len(i.partition.names)})" for i in t.inputs)
        tables.add_row(t.name, sets, f"{t.rule_count:,}")
    out.print(tables)
    columns = ("configuration", "rules", "held-out error (m/s)")
    scores = table(
        *columns,
        title=f"trained on {counted(summary.design.train_episodes, 'episode')}, "
        f"scored on {summary.design.heldout_episodes} held out",
        right=columns[1:],
    )
    for s in summary.design.scores:
        scores.add_row(s.config, f"{s.rules:,}", f"{s.error_mps:.3f}")
    out.print(scores)
    for repeat in summary.repeated_sessions:
        out.print(f"used once: {repeat.text()}")
    record = summary.document()["inputs"]["method"]
    out.print(f"method: {trained_method(record, choice)}", soft_wrap=True, markup=False)
    out.print(f"{summary.wall_s:.1f} s of wall-clock time")
