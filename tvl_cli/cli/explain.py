"""`tvl explain`: one moment of a run trace in the rules of its FAM, or its contact autopsy.

The command imports the modules that do its work when it runs, so that `--help` reads only
the options (and loads neither HDF5 nor the physics).
"""

from __future__ import annotations

from pathlib import Path

import click

from tvl_cli.cli import views
from tvl_cli.cli.examples import examples
from tvl_cli.cli.options import PICTURE, print_json, refuse_outputs
from tvl_cli.core.contacts import EVENT_CHOICES
from tvl_cli.core.errors import BadInput


@click.command(epilog=examples("explain"))
@click.argument("trace", metavar="RUN", type=click.Path(path_type=Path))
@click.option("--step", type=click.IntRange(min=0), default=None, help="The step, 0 the first.")
@click.option(
    "--at", "at_s", type=float, default=None, help="Simulated seconds, as replay lists events."
)
@click.option("--event", type=click.Choice(EVENT_CHOICES), default=None, help="An event's step.")
@click.option(
    "--index", type=click.IntRange(min=1), default=1, show_default=True, help="The K-th event."
)
@click.option(
    "--fam",
    "fam_path",
    type=click.Path(path_type=Path),
    default=None,
    help="The FAM the run used, if it is no longer where the trace says.",
)
@click.option(
    "--contacts",
    is_flag=True,
    help="The contact autopsy instead: every contact's cause, where the time went and why "
    "a goal was missed.",
)
@click.option(
    "--png",
    type=PICTURE,
    default=None,
    help="Draw the moment: the pose, the rays, the trajectories of the view with the fast "
    "set, the perceived velocities and the strongest rules that fired.",
)
@click.option("--force", is_flag=True, help="Overwrite the --png file.")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
def explain(
    trace: Path,
    step: int | None,
    at_s: float | None,
    event: str | None,
    index: int,
    fam_path: Path | None,
    contacts: bool,
    png: Path | None,
    force: bool,
    as_json: bool,
) -> None:
    """Explain one moment of a run trace in the rules of its FAM.

    What the robot read and perceived, what it chose and why; or, with --contacts, why each
    contact of the run happened."""
    if contacts:
        if any(x is not None for x in (step, at_s, event)):
            raise BadInput("--contacts explains the whole run: give no --step, --at or --event")
        if png is not None:
            raise BadInput("--png draws one moment: it is not for --contacts")
        from tvl_cli.commands.contact_autopsy import trace_autopsy

        autopsy = trace_autopsy(trace)
        if as_json:
            print_json(autopsy.document())
        else:
            views.autopsy(autopsy.autopsy)
        return
    from tvl_cli.commands.explain import Moment, explain_run

    if png is not None:
        refuse_outputs({"--png": png}, {"RUN": trace, "--fam": fam_path}, force)
    found = explain_run(trace, Moment(step, at_s, event, index), fam_path, png)
    if found.moved:
        click.echo(found.moved, err=True)
    if as_json:
        print_json(found.document())
    else:
        views.step_explanation(found)
