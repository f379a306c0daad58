"""The `tvl` command line: click commands that parse, call one function and render the result."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from tvl_cli import __version__
from tvl_cli.core.errors import BadInput


class TvlGroup(click.Group):
    """Turns BadInput into one line on stderr and exit 2; --debug shows the traceback."""

    def invoke(self, ctx: click.Context) -> object:
        try:
            return super().invoke(ctx)
        except BadInput as error:
            if ctx.obj and ctx.obj.get("debug"):
                raise
            click.echo(f"tvl: error: {error}", err=True)
            sys.exit(2)


@click.group(cls=TvlGroup)
@click.version_option(__version__, prog_name="tvl")
@click.option("--debug", is_flag=True, help="Show the traceback of an error.")
@click.pass_context
def main(ctx: click.Context, debug: bool) -> None:
    """Trajectory Velocity Learning for a simulated sonar-ring mobile robot."""
    ctx.obj = {"debug": debug}


def refuse_existing(path: Path, force: bool) -> None:
    """Output files are never overwritten unless the user says --force."""
    if path.exists() and not force:
        raise BadInput(f"{path}: already exists (use --force to overwrite)")


# --- world commands ---------------------------------------------------------------

# --- FAM commands: train, inspect -------------------------------------------------

# --- learn, run, replay, demo -----------------------------------------------------
