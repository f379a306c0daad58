"""The experiment figures (paper §5) by the names `tvl figure` knows them by: each draws
from the numbers the analysis modules compute out of a sweep's rows, and also returns its
summary table."""

from __future__ import annotations

from collections.abc import Callable

from matplotlib.figure import Figure

from tvl_cli.analysis.result_rows import Row
from tvl_cli.render.ablation_figure import ablation
from tvl_cli.render.exploration_figure import exploration
from tvl_cli.render.goal_figure import figure22
from tvl_cli.render.learning_curve_figures import figure19, figure24, figure27
from tvl_cli.render.online_figure import online
from tvl_cli.render.wall_threshold_figure import figure21

FIGURES: dict[str, Callable[[list[Row]], tuple[Figure, str]]] = {
    "fig19": figure19,
    "fig21": figure21,
    "fig22": figure22,
    "fig24": figure24,
    "fig27": figure27,
    "ablation": ablation,
    "online": online,
    "exploration": exploration,
}
