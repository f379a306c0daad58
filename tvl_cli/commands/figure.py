"""`tvl figure`: one of the paper's figures (or an experiment's) from a sweep's results: the
rows read and checked, the traces of the goal runs read in, the picture and its table
written."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tvl_cli.analysis.figure_needs import check_needs
from tvl_cli.analysis.result_rows import Row, read_results
from tvl_cli.core.errors import BadInput
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.json_documents import document, input_file, output_path
from tvl_cli.io.runfile import read_run

DPI = 120  # of a raster picture


@dataclass(frozen=True, slots=True)
class FigureRequest:
    name: str  # one of render.experiment_figures.FIGURES
    results: Path  # a sweep's results.jsonl
    picture: Path  # in the format its extension names
    table: Path | None = None  # the summary table as markdown


@dataclass(frozen=True, slots=True)
class Drawn:
    """A figure drawn as asked, and its summary table (markdown)."""

    request: FigureRequest
    summary: str

    def document(self) -> dict[str, Any]:
        r = self.request
        return document(
            "figure",
            {"figure": r.name, "results": input_file(r.results)},
            outputs={"picture": str(r.picture), "table": output_path(r.table)},
            summary_markdown=self.summary,
        )


def draw(request: FigureRequest) -> Drawn:
    """Draw the figure and write its table."""
    # matplotlib is slow to import: only drawing needs it.
    from tvl_cli.render.experiment_figures import FIGURES
    from tvl_cli.render.formats import save_picture

    name, results = request.name, request.results
    if name not in FIGURES:
        raise BadInput(f"unknown figure {name!r} (choose from {', '.join(FIGURES)})")
    by_line = read_results(results)
    if not by_line:
        raise BadInput(f"{results}: no runs")
    check_needs(name, by_line, str(results))
    rows = [_with_trace(row, results.parent) for row in by_line.values()]
    try:
        figure, summary = FIGURES[name](rows)
    except KeyError as error:
        raise BadInput(f"{results}: a run lacks the key {error} that {name} needs") from None
    save_picture(figure, request.picture, dpi=DPI)
    if request.table is not None:
        with atomic_output(request.table) as temporary:
            temporary.write_text(summary, encoding="utf-8")
    return Drawn(request, summary)


def _with_trace(row: Row, base: Path) -> Row:
    """A run with a trace (`trace_file`, relative to the results) with its path and world."""
    if not row.get("trace_file"):
        return row
    trace = read_run(base / row["trace_file"])
    return {**row, "pose": trace.arrays["pose"], "world_text": trace.world_text}
