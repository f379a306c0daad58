"""`tvl figure`: one of the paper's figures from an experiment's results."""

from __future__ import annotations

from pathlib import Path

import click

from tvl_cli.cli import views
from tvl_cli.cli.examples import examples
from tvl_cli.cli.options import MARKDOWN, PICTURE, PICTURE_HELP, print_json, refuse_outputs
from tvl_cli.cli.params import complete_figure
from tvl_cli.commands.figure import FigureRequest, draw


@click.command(epilog=examples("figure"))
@click.argument("name", metavar="NAME", shell_complete=complete_figure)
@click.argument("results", type=click.Path(path_type=Path))
@click.option("-o", "--output", type=PICTURE, required=True, help=PICTURE_HELP)
@click.option("--table", type=MARKDOWN, default=None, help="Markdown file (.md).")
@click.option("--force", is_flag=True, help="Overwrite the picture and table files.")
@click.option("--json", "as_json", is_flag=True, help="Print the files and the table as JSON.")
def figure(
    name: str, results: Path, output: Path, table: Path | None, force: bool, as_json: bool
) -> None:
    """Draw figure NAME (fig19, fig21, fig22, fig24, fig27, ablation, online, exploration)
    from an experiment's RESULTS (JSON lines) and print its summary table.

    RESULTS is the results.jsonl of the experiment's sweep: `tvl sweep
    experiments/grids/NAME.toml --out DIR` writes DIR/results.jsonl."""
    refuse_outputs({"-o": output, "--table": table}, {"RESULTS": results}, force)
    drawn = draw(FigureRequest(name, results, output, table))
    if as_json:
        print_json(drawn.document())
    else:
        # Its tables and notes laid out for the terminal's width; --table keeps the markdown.
        views.markdown_summary(drawn.summary)
