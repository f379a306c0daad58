"""`tvl demo`: learn, train, run and draw on a bundled world, the whole pipeline at once."""

from __future__ import annotations

from pathlib import Path

import click

from tvl_cli.cli import views
from tvl_cli.cli.examples import examples
from tvl_cli.cli.options import print_json


@click.command(epilog=examples("demo"))
@click.argument("directory", default="tvl-demo", type=click.Path(path_type=Path))
@click.option("--force", is_flag=True, help="Write into a DIRECTORY that is not empty.")
@click.option("--json", "as_json", is_flag=True, help="Print the results as JSON.")
def demo(directory: Path, force: bool, as_json: bool) -> None:
    """Learn, train, run and draw on a bundled world, in seconds."""
    from tvl_cli.commands.demo import run_demo

    result = run_demo(directory, force, views.say)
    if as_json:
        print_json(result.document())
    else:
        views.demo(result)
