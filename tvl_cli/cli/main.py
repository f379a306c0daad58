"""The `tvl` group: one line on stderr for bad input, and commands loaded when used.

Each command lives in a module of its own, imported only when it runs or shows its help, so
that `tvl --help` starts without numpy, h5py, pymunk or matplotlib.
"""

from __future__ import annotations

import difflib
import errno
import gc
import importlib
import os
import re
import sys
from typing import NoReturn

import click

from tvl_cli import __version__
from tvl_cli.cli.examples import examples
from tvl_cli.core.errors import BadInput, EnvironmentFailure
from tvl_cli.io.interrupts import STOPPED_EXIT

# name -> the line `tvl --help` shows for it. Each verb is the command of its name in
# tvl_cli.cli.<name>. The line is kept here so that the top-level help needs no import; a
# test holds it to the command's own first line.
COMMANDS: dict[str, str] = {
    "world": "Make, check, show and draw text-map worlds; import and export occupancy grids.",
    "learn": "Explore WORLD and learn trajectory velocities, recording every episode in a log.",
    "train": "Train a FAM file from learning logs (log replay).",
    "inspect": "Print a FAM file's rules as a person reads them.",
    "diff": "Show where two FAM files of one configuration disagree, rule by rule.",
    "design": "Choose each FAM table's sonars and fuzzy sets from learning logs.",
    "run": "Perform a behaviour in WORLD with a learnt FAM.",
    "replay": "Summarise a learning log or a run trace, and draw it.",
    "explain": "Explain one moment of a run trace in the rules of its FAM.",
    "demo": "Learn, train, run and draw on a bundled world, in seconds.",
    "baseline": "Controllers to measure TVL against: DWA and tabular Q-learning.",
    "sweep": "Learn, train and run every combination of a grid's settings into one results table.",
    "bench": "Benchmark suites: generalization to worlds nobody tuned on, and the paper's claims.",
    "export": "Write a run trace as MCAP, in Foxglove's schemas, to play back in Foxglove.",
    "figure": (
        "Draw figure NAME (fig19, fig21, fig22, fig24, fig27, ablation, online, exploration) "
        "from an experiment's RESULTS (JSON lines) and print its summary table."
    ),
    "schema": "Print the JSON Schema of COMMAND's --json output; with no COMMAND, list them.",
}


def command_named(name: str) -> click.Command:
    """The command `tvl NAME` runs; its module is imported only now."""
    command = getattr(importlib.import_module(f"tvl_cli.cli.{name}"), name)
    assert isinstance(command, click.Command)
    return command


# Failures of the machine rather than of what the user typed: no space, no memory, a broken
# or read-only disk.
ENVIRONMENT_ERRNOS = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EIO, errno.ENOMEM, errno.EROFS})
# Of those, the ones that stop a write part way: no space, over quota, over the size limit.
WRITE_ERRNOS = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EFBIG})


class TvlGroup(click.Group):
    """Loads commands on demand; turns BadInput into one line on stderr and exit 2, what the
    machine lacks (EnvironmentFailure) into one line and exit 1, and an operating-system
    error into one line and exit 1 or 2 (--debug shows the traceback)."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return list(COMMANDS)

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        if cmd_name not in COMMANDS:
            return None
        return command_named(cmd_name)

    def resolve_command(
        self, ctx: click.Context, args: list[str]
    ) -> tuple[str | None, click.Command | None, list[str]]:
        # click suggests among the commands it holds, and this group holds none until used:
        # the suggestion a subgroup's mistyped command gets, from the registry.
        name = args[0]
        if name not in COMMANDS and not name.startswith("-") and not ctx.resilient_parsing:
            close = difflib.get_close_matches(name, COMMANDS, n=1)
            suggestion = f" Did you mean {close[0]!r}?" if close else ""
            ctx.fail(f"No such command {name!r}.{suggestion}")
        return super().resolve_command(ctx, args)

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        rows = list(COMMANDS.items())
        with formatter.section("Commands"):
            formatter.write_dl(rows)

    def invoke(self, ctx: click.Context) -> object:
        try:
            try:
                return super().invoke(ctx)
            finally:
                # The work is done and its files closed: the collector's last pass at exit
                # would only walk every object left (in a large world's physics, most of a
                # second after Ctrl-C) to free memory the process gives back anyway.
                gc.freeze()
        except BadInput as error:
            if ctx.obj and ctx.obj.get("debug"):
                raise
            click.echo(f"tvl: error: {error}", err=True)
            sys.exit(2)
        except EnvironmentFailure as error:
            if ctx.obj and ctx.obj.get("debug"):
                raise
            click.echo(f"tvl: error: {error}", err=True)
            sys.exit(1)
        except (OSError, RuntimeError) as error:
            if ctx.obj and ctx.obj.get("debug"):
                raise
            refused = _refused_write(error)
            if refused:
                # HDF5 cannot close a file it failed to write, and crashes trying at exit: say
                # so and leave now. What was committed stays readable, as after a kill.
                click.echo(f"tvl: error: {_file_of(error)}{refused}", err=True)
                sys.stderr.flush()
                os._exit(1)
            if not isinstance(error, OSError):
                raise
            # What the system refused outside any check of ours: the machine's fault (exit 1),
            # or else a path the user named (exit 2).
            where = f"{error.filename}: " if error.filename else ""
            click.echo(f"tvl: error: {where}{error.strerror or error}", err=True)
            sys.exit(1 if error.errno in ENVIRONMENT_ERRNOS else 2)
        except click.UsageError as error:
            _refuse_usage(error)
        except KeyboardInterrupt:
            # Ctrl-C where no command catches it (a long command stops at its own pace and
            # says what it kept): the shell's status for it, and not click's "Aborted!".
            click.echo("tvl: interrupted", err=True)
            sys.exit(STOPPED_EXIT["SIGINT"])

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        # The group's own options are parsed before invoke: their errors too are one line.
        try:
            return super().parse_args(ctx, args)
        except click.UsageError as error:
            _refuse_usage(error)


# What click (8.2 on) raises for a group given no command, to show its help: not an error.
_HELP_FOR_NO_COMMAND = getattr(click.exceptions, "NoArgsIsHelpError", ())


def _refuse_usage(error: click.UsageError) -> NoReturn:
    """A usage error in one line like every other bad input, exit 2, ending with click's
    hint ("Try 'tvl COMMAND -h' for help."), which click would put on a line of its own."""
    if isinstance(error, _HELP_FOR_NO_COMMAND):
        raise error  # click prints the help
    command = f" {error.ctx.command_path}" if error.ctx else ""
    message = " ".join(error.format_message().split())  # click lists choices on lines
    if error.ctx is not None and error.ctx.command.get_help_option(error.ctx) is not None:
        ended = message if message.endswith((".", "?", "!")) else f"{message}."
        asking = f"{error.ctx.command_path} {error.ctx.help_option_names[0]}"
        message = f"{ended} Try '{asking}' for help."
    click.echo(f"tvl: error:{command}: {message}", err=True)
    sys.exit(2)


def _refused_write(error: BaseException) -> str | None:
    """Why the machine refused a write (no space, over quota, over the file size limit), as
    the OS or HDF5 (inside its own message) says it; None for any other error."""
    for cause in (error, error.__cause__, error.__context__):
        if isinstance(cause, OSError) and cause.errno in WRITE_ERRNOS:
            return os.strerror(cause.errno)
        found = re.search(r"errno = (\d+)", str(cause)) if cause is not None else None
        if found and int(found.group(1)) in WRITE_ERRNOS:
            return os.strerror(int(found.group(1)))
    return None


def _file_of(error: BaseException) -> str:
    """The file named in the error, as a prefix; HDF5 gives it as "filename = '...'"."""
    from tvl_cli.io.atomic import output_named_by  # only on an error: keeps start-up quick

    if isinstance(error, OSError) and error.filename:
        return f"{output_named_by(str(error.filename))}: "
    named = re.search(r"filename = '([^']*)'", str(error))
    return f"{output_named_by(named.group(1))}: " if named else ""


# -h as well as --help, for the group and (inherited through the context) every command.
@click.group(
    cls=TvlGroup,
    context_settings={"help_option_names": ["-h", "--help"]},
    epilog=examples(""),
)
@click.version_option(__version__, prog_name="tvl")
@click.option("--debug", is_flag=True, help="Show the traceback of an error.")
@click.pass_context
def main(ctx: click.Context, debug: bool) -> None:
    """Trajectory Velocity Learning for a simulated sonar-ring mobile robot."""
    ctx.obj = {"debug": debug}
