"""Figure 21 (paper §5.1): wall following against the velocity threshold, dashed where
collision prone, beside the ends the paper reports; with its summary table."""

from __future__ import annotations

from itertools import pairwise

from matplotlib.axes import Axes
from matplotlib.figure import Figure

from tvl_cli.analysis.aggregation import distinct, select
from tvl_cli.analysis.intervals import Interval
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.result_text import (
    WORLD_ORDER,
    interval_text,
    markdown,
    method_label,
    methods_of,
)
from tvl_cli.analysis.wall_threshold import (
    COLLISION_PRONE_PER_MIN,
    PAPER_FIG21,
    prone,
    threshold_points,
)
from tvl_cli.render.figure_parts import PAPER_COLOUR, new_figure

Point = dict[str, Interval | None]
# How far apart along the threshold axis the series' points stand (thresholds are 0.05 apart).
SERIES_OFFSET = 0.004


def dashed_where_prone(
    ax: Axes, points: list[tuple[float, Point]], key: str, colour: str, offset: float = 0.0
) -> None:
    """Solid between safe settings, dashed where either end is collision prone (paper Fig. 21);
    hollow markers on the collision-prone settings themselves, with their 95 % intervals,
    `offset` along the threshold axis so that the series' bars stand apart."""
    points = [(threshold + offset, point) for threshold, point in points]
    for (t1, p1), (t2, p2) in pairwise(points):
        a, b = p1[key], p2[key]
        if a is not None and b is not None:
            style = "--" if prone(p1) or prone(p2) else "-"
            ax.plot([t1, t2], [a.mean, b.mean], style, color=colour)
    for threshold, point in points:
        shown = point[key]
        if shown is not None:
            face = "white" if prone(point) else colour
            half = shown.half_width
            ax.errorbar(
                threshold,
                shown.mean,
                yerr=None if half is None else half,
                fmt="o",
                color=colour,
                markerfacecolor=face,
                capsize=2,
            )


def figure21(rows: list[Row]) -> tuple[Figure, str]:
    tvl = select(rows, kind="tvl")
    worlds = distinct(tvl, "world", WORLD_ORDER)
    methods = methods_of(tvl)
    figure = new_figure(10, 4.2)
    clearance, speed = figure.subplots(1, 2)
    body = []
    series = [(m, w) for m in methods for w in worlds]
    for index, (method, world) in enumerate(series):
        colour = f"C{index}"
        points = threshold_points(select(tvl, method=method), world)
        offset = (index - (len(series) - 1) / 2) * SERIES_OFFSET
        dashed_where_prone(clearance, points, "mean_wall_clearance_m", colour, offset)
        dashed_where_prone(speed, points, "mean_speed_mps", colour, offset)
        clearance.plot([], [], color=colour, label=f"{world}, {method_label(method)}")
        for threshold, p in points:
            body.append(
                [
                    world,
                    method_label(method),
                    f"{threshold:.2f}",
                    interval_text(p["mean_wall_clearance_m"]),
                    interval_text(p["mean_speed_mps"]),
                    interval_text(p["contacts_per_min"]),
                    "yes" if prone(p) else "no",
                ]
            )
    ends = sorted(PAPER_FIG21)
    for ax, index in ((clearance, 0), (speed, 1)):
        values = [PAPER_FIG21[t][index] for t in ends]
        ax.plot(ends, values, "x:", color=PAPER_COLOUR, label="paper (ends only)")
    clearance.plot([], [], "k--", label="collision prone")
    clearance.legend(fontsize=7)
    clearance.set_ylabel("mean wall clearance (m)")
    speed.set_ylabel("mean speed (m/s)")
    for ax in (clearance, speed):
        ax.set_xlabel("velocity threshold (fraction of each trajectory's maximum)")
        ax.grid(alpha=0.3)
    figure.suptitle(
        "Wall following against the velocity threshold (mean and 95 % interval over trials)"
    )
    table = markdown(
        "Figure 21: wall following against the velocity threshold",
        ("world", "method", "threshold", "wall clearance m", "speed m/s", "contacts/min", "prone"),
        body,
    )
    (low, (low_m, low_mps)), (high, (high_m, high_mps)) = sorted(PAPER_FIG21.items())
    note = (
        f"Mean ± 95 % interval over trials (each trial's wall sides averaged). Collision "
        f"prone: more than {COLLISION_PRONE_PER_MIN:g} contacts/min. "
        f"Paper (§5.1): threshold {low:g} → {high:g}, wall clearance {low_m:g} → {high_m:g} m, "
        f"mean speed {low_mps:g} → {high_mps:g} m/s.\n"
    )
    return figure, table + "\n" + note
