"""What the experiment figures share: a new figure; the colours and line styles of the
configurations, methods and baselines; reference lines and competence limits; the collision
axis; one legend under the panels; a mean curve with its 95 % band; a bar of time to
competence."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from tvl_cli.analysis.aggregation import curve, curve_band, mean, select
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.time_to_competence import qlearn_checks
from tvl_cli.core import competence
from tvl_cli.core.method import DEFAULT_NAME, PAPER_NAME

CONFIG_STYLE = {"single": "#1f77b4", "multi": "#d62728"}
DWA_COLOUR, QLEARN_COLOUR = "#2ca02c", "#9467bd"
PAPER_COLOUR = "grey"


def new_figure(width_in: float, height_in: float) -> Figure:
    figure = Figure(figsize=(width_in, height_in), layout="constrained")
    FigureCanvasAgg(figure)
    return figure


def reference_line(ax: Axes, value: float | None, colour: str, label: str) -> None:
    if value is not None:
        ax.axhline(value, color=colour, linestyle="--", linewidth=1.2, label=label)


# A shared legend's entries a row: more would run off a figure of one or two panels.
LEGEND_COLUMNS = 4


def shared_legend(figure: Figure, axes: Iterable[Axes]) -> None:
    """One legend under the panels, each label once."""
    handles: dict[str, Any] = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(label, handle)
    figure.legend(
        list(handles.values()),
        list(handles),
        loc="outside lower center",
        ncols=min(len(handles), LEGEND_COLUMNS),
    )


def competence_limit(ax: Axes, value: float) -> None:
    ax.axhline(value, color="grey", linestyle=":", linewidth=1, label="competence limit")


def collision_axis(ax: Axes) -> None:
    """Collision rates span 0 to tens per minute; symlog keeps the 0.2 limit readable.
    Call it after the lines are drawn: the top leaves room above the highest."""
    ax.set_yscale("symlog", linthresh=0.1)
    ax.autoscale_view()
    ax.set_ylim(0, 2 * ax.get_ylim()[1])


def baselines_and_limits(hits: Axes, speed: Axes, rows: list[Row], world: str) -> None:
    """On the avoid-run panels: DWA's level, Q-learning's checks, the competence limits."""
    dwa = select(rows, kind="dwa", world=world, behaviour="avoid")
    reference_line(hits, mean(r["contacts_per_min"] for r in dwa), DWA_COLOUR, "DWA")
    reference_line(speed, mean(r["mean_speed_mps"] for r in dwa), DWA_COLOUR, "DWA")
    checks = qlearn_checks(select(rows, kind="qlearn", world=world))
    if checks:
        for ax, key in ((hits, "contacts_per_min"), (speed, "mean_speed_mps")):
            ax.plot(*curve(checks, "minute", key), "-.", color=QLEARN_COLOUR, label="Q-learning")
    competence_limit(hits, competence.MAX_CONTACTS_PER_MIN)
    competence_limit(speed, competence.MIN_MEAN_SPEED_MPS)
    collision_axis(hits)


# Each method's line style beside the others: ours solid, the paper's dashed, others dotted.
METHOD_LINES = {DEFAULT_NAME: "-", PAPER_NAME: "--"}
# Bars of a method other than ours: paler, beside ours in the same colour.
OTHER_METHOD_ALPHA = 0.5
# A band of the 95 % interval over trials: faint, so that the lines read through it.
BAND_ALPHA = 0.18


def method_line(method: str) -> str:
    return METHOD_LINES.get(method, ":")


def band_curve(
    ax: Axes, rows: list[Row], x: str, y: str, style: str, colour: str, label: str
) -> None:
    """The mean over trials of `y` against `x` as a line, and its 95 % interval as a band."""
    xs, means, halves = curve_band(rows, x, y)
    ax.plot(xs, means, style, ms=3, color=colour, label=label)
    known = ~np.isnan(halves)
    if known.any():
        ax.fill_between(
            xs[known],
            (means - halves)[known],
            (means + halves)[known],
            color=colour,
            alpha=BAND_ALPHA,
            linewidth=0,
        )


def competence_bar(times: Sequence[float | None], horizon_min: float) -> tuple[float, str]:
    """Bar height (mean of the competent trials, the horizon if none) and hatch (some not)."""
    reached = [t for t in times if t is not None]
    height = sum(reached) / len(reached) if reached else horizon_min
    return height, "" if len(reached) == len(times) else "//"
