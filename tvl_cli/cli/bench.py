"""`tvl bench`: the shipped suites, run on the sweep's engine, and any controller scored."""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click

from tvl_cli.cli import bench_view, views
from tvl_cli.cli.examples import examples
from tvl_cli.cli.groups import Subcommands
from tvl_cli.cli.options import print_json
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.sweep.executors import DEFAULT_SCHEDULER_TIMEOUT_S

SIZES = ("tiny", "quick", "full")
Command = TypeVar("Command", bound=Callable[..., Any])


@click.group(cls=Subcommands, epilog=examples("bench"))
def bench() -> None:
    """Benchmark suites: generalization to worlds nobody tuned on, and the paper's claims."""


def where_options(suite: str) -> Callable[[Command], Command]:
    """The options every suite shares: its size, its directory, where its cells run, and
    how its figures are printed."""

    def decorate(command: Command) -> Command:
        for option in reversed(
            [
                click.option(
                    "--size",
                    type=click.Choice(SIZES),
                    default="full",
                    show_default=True,
                    help="full: the benchmark as reported; quick: a smaller look; tiny: "
                    "seconds, that every row is made.",
                ),
                click.option(
                    "--out",
                    type=click.Path(path_type=Path),
                    default=Path("results") / f"bench-{suite}",
                    show_default=True,
                    help="The bench's directory: logs, FAMs and every cell's rows. Running "
                    "again goes on where it stopped.",
                ),
                click.option(
                    "--workers",
                    type=click.IntRange(min=1),
                    default=None,
                    help="Local processes (default: one a core).",
                ),
                click.option(
                    "--scheduler",
                    metavar="local[:N]|tcp://HOST:PORT",
                    default=None,
                    help="Run the cells on a Dask cluster: local[:N] starts one here, an "
                    "address uses that scheduler's workers (needs tvl[sweep]).",
                ),
                click.option(
                    "--scheduler-timeout",
                    "scheduler_timeout_s",
                    type=click.FloatRange(min=0.0, min_open=True),
                    default=DEFAULT_SCHEDULER_TIMEOUT_S,
                    show_default=True,
                    help="Seconds a scheduler has to answer.",
                ),
                click.option("--markdown", is_flag=True, help="Print the tables as Markdown."),
                click.option("--json", "as_json", is_flag=True, help="Print a JSON document."),
            ]
        ):
            command = option(command)
        return command

    return decorate


def _where(out: Path, workers: int | None, scheduler: str | None, timeout_s: float) -> Any:
    from tvl_cli.bench.suite_runner import Where  # the engine only when a suite runs

    if workers is not None and scheduler is not None:
        raise click.UsageError("give --workers or --scheduler, not both (a cluster has its own)")
    return Where(out, workers or os.cpu_count() or 1, scheduler, timeout_s)


def _running(as_json: bool, run: Callable[..., Any]) -> Any:
    """The suite run under a progress bar of its cells; a Ctrl-C says where its rows are."""

    def on_dashboard(link: str) -> None:
        if not as_json:
            views.say(f"dashboard: {link}")

    try:
        with views.progress("cells", quiet=as_json) as bar:
            return run(bar, on_dashboard)
    except KeyboardInterrupt:
        views.say("interrupted: the cells that ended are in the bench's directory; run again")
        sys.exit(130)


@bench.command("generalization", epilog=examples("bench generalization"))
@click.option(
    "--set",
    "world_set",
    type=click.Choice(("test", "tuning")),
    default="test",
    show_default=True,
    help="The worlds: test (rooms seeds 1001-1020, for reporting only) or tuning (1-20).",
)
@click.option(
    "--worlds",
    "span",
    metavar="N|A-B",
    default=None,
    help="The set's first N worlds, or its A-th to B-th (default: the size's).",
)
@click.option(
    "--trials", type=click.IntRange(min=1), default=None, help="Trials (default: the size's)."
)
@click.option(
    "--method",
    default="default",
    show_default=True,
    help="Ours: a preset (default, paper) or a method file.",
)
@click.option(
    "--config",
    "configs",
    multiple=True,
    help="A FAM configuration trained from each log: single, multi, designed or a file "
    "(repeatable; default the three shipped).",
)
@click.option(
    "--controller",
    "controllers",
    multiple=True,
    metavar="[NAME=]SPEC",
    help="Score this beside ours (repeatable): a method (preset or FILE.toml), a FAM file, "
    "a Gymnasium policy (MODULE:CALLABLE or FILE.py:CALLABLE) or a Stable-Baselines3 "
    "model (ALGORITHM:FILE.zip).",
)
@click.option(
    "--observe",
    default=None,
    help="The method whose sonar and echo memory policies and models observe through, as "
    "tvl/SonarRing-v0's method= (default: --method's).",
)
@click.option(
    "--references",
    default="all",
    show_default=True,
    metavar="all|none|NAME,...",
    help="The reference rows: oracle-velocities, oracle-labels, ideal-sonar, dwa-map, "
    "dwa-ring, q-learning.",
)
@click.option("--threshold", type=float, default=DEFAULT_THRESHOLD, show_default=True)
@click.option(
    "--pool",
    multiple=True,
    metavar="LOG",
    help="Also train ours' FAMs from each world's log pooled with this log learnt elsewhere, "
    "as the rows `pooled` (repeatable; e.g. fams/general-log.h5).",
)
@click.option(
    "--by-world",
    "each_world",
    is_flag=True,
    help="Also print, world by world, each row's competent runs and mean speed there.",
)
@where_options("generalization")
def generalization(**options: Any) -> None:
    """Learn, train and run in generated rooms worlds nobody tuned on, beside references and
    any controller given; print competence, goals, contacts and speed over the trials."""
    from tvl_cli.bench.generalization_suite import run_generalization
    from tvl_cli.bench.suite_options import generalization_request

    as_json, markdown = options.pop("as_json"), options.pop("markdown")
    each_world = options.pop("each_world")
    where = _where(
        options.pop("out"),
        options.pop("workers"),
        options.pop("scheduler"),
        options.pop("scheduler_timeout_s"),
    )
    request = generalization_request(**options)
    result = _running(as_json, lambda bar, dash: run_generalization(request, where, bar, dash))
    if as_json:
        print_json(result.document())
    else:
        bench_view.show_generalization(result, where, markdown, each_world)


@bench.command("claims", epilog=examples("bench claims"))
@click.option(
    "--method",
    "methods",
    multiple=True,
    help="A method each claim is learnt, trained and run by: a preset or a method file "
    "(repeatable; default paper and default).",
)
@click.option(
    "--claim",
    "claims",
    multiple=True,
    help="Only this claim (repeatable): avoid-9min, fig21, fig22, fig24, fig27.",
)
@where_options("claims")
def claims(**options: Any) -> None:
    """Run five of the paper's claims (§5) by the paper's method and ours, and say which are
    met, with the trials' means and intervals."""
    from tvl_cli.bench.claims_suite import METHODS, ClaimsRequest, check_claims, run_claims

    as_json, markdown = options.pop("as_json"), options.pop("markdown")
    where = _where(
        options.pop("out"),
        options.pop("workers"),
        options.pop("scheduler"),
        options.pop("scheduler_timeout_s"),
    )
    methods = options["methods"] or METHODS
    if len(set(methods)) < len(methods):
        raise click.UsageError("--method: a method is given twice")
    request = ClaimsRequest(tuple(methods), check_claims(options["claims"]), options["size"])
    result = _running(as_json, lambda bar, dash: run_claims(request, where, bar, dash))
    if as_json:
        print_json(result.document())
    else:
        bench_view.show_claims(result, where, markdown)
