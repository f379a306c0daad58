"""Figure 22: goal seeking, the paths of each world's first trial and how many trials of each
method reached each goal; with its summary table."""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from tvl_cli.analysis.aggregation import distinct, mean, seed_interval, select
from tvl_cli.analysis.goal_series import goal_methods
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.result_text import (
    WORLD_ORDER,
    interval_text,
    markdown,
    method_label,
    methods_of,
    number,
)
from tvl_cli.render.figure_parts import new_figure
from tvl_cli.render.plot import draw_world
from tvl_cli.sim.worldmap import parse_world


def draw_paths(ax: Axes, runs: list[Row]) -> None:
    """The world and the recorded paths of one trial's goal runs (the `pose` arrays, N x 3
    m, m, rad, and `world_text` of their traces, which commands.figure reads in)."""
    traced = [r for r in runs if "pose" in r]
    if not traced:
        ax.set_axis_off()
        return
    draw_world(ax, parse_world(traced[0]["world_text"], traced[0]["trace_file"]))
    for run in traced:
        pose = run["pose"]
        colour = f"C{run['goal_index'] - 1}"
        style = "-" if run["goal_reached"] else ":"
        ax.plot(pose[:, 0], pose[:, 1], style, color=colour, linewidth=1.4, zorder=4)
        gx, gy = (float(v) for v in run["goal"].split(","))
        ax.annotate(
            str(run["goal_index"]),
            (gx, gy),
            xytext=(5, 5),
            textcoords="offset points",
            color=colour,
            fontweight="bold",
        )


def numbered_goals(goal_runs: list[Row]) -> list[Row]:
    """The goal runs with each goal's number in its world (`goal_index`, from 1), in the order
    the runs first seek them."""
    numbers: dict[tuple[str, str], int] = {}
    for run in goal_runs:
        in_world = sum(world == run["world"] for world, _ in numbers)
        numbers.setdefault((run["world"], run["goal"]), in_world + 1)
    return [{**run, "goal_index": numbers[run["world"], run["goal"]]} for run in goal_runs]


def figure22(rows: list[Row]) -> tuple[Figure, str]:
    goal_runs = numbered_goals(select(rows, behaviour="goal"))
    worlds = distinct(goal_runs, "world", WORLD_ORDER)
    tvl = select(goal_runs, kind="tvl")
    panels = [
        (method, config)
        for method in methods_of(tvl)
        for config in distinct(select(tvl, method=method), "config", ("single", "multi"))
    ]
    columns = len(panels) + 1
    figure = new_figure(4.6 * columns, 3.8 * len(worlds))
    axes = figure.subplots(len(worlds), columns, squeeze=False)
    body = []
    for row_index, world in enumerate(worlds):
        in_world = select(goal_runs, world=world)
        for column, (method, config) in enumerate(panels):
            tvl_runs = select(in_world, kind="tvl", config=config, method=method)
            trial = min((r["seed"] for r in tvl_runs), default=None)
            draw_paths(axes[row_index, column], select(tvl_runs, seed=trial))
            axes[row_index, column].set_title(
                f"{world}, {config} FAM, {method_label(method)}, trial {trial}", fontsize=9
            )
        bars = axes[row_index, -1]
        goals = distinct(in_world, "goal_index")
        methods = goal_methods(in_world)
        width = 0.8 / max(len(methods), 1)
        for m, (label, runs) in enumerate(methods):
            successes = [sum(r["goal_reached"] for r in select(runs, goal_index=g)) for g in goals]
            bars.bar(np.arange(len(goals)) + m * width, successes, width, label=label)
        for goal in goals:
            at_goal = select(in_world, goal_index=goal)
            cells = [world, str(goal), at_goal[0]["goal"]]
            for _, runs in methods:
                runs = select(runs, goal_index=goal)
                reached = [r for r in runs if r["goal_reached"]]
                time_s = mean(r["time_to_goal_s"] for r in reached)
                cells.append(f"{len(reached)}/{len(runs)} ({number(time_s, 0)} s)")
            body.append(cells)
        # Each trial's share of the world's goals reached: mean and 95 % interval.
        body.append(
            [world, "all", "share reached"]
            + [interval_text(seed_interval(runs, "goal_reached")) for _, runs in methods]
        )
        bars.set_xticks(np.arange(len(goals)) + 0.4 - width / 2, [str(g) for g in goals])
        bars.set_xlabel("goal")
        bars.set_ylim(0, len(distinct(in_world, "seed")) + 0.2)
        bars.yaxis.set_major_locator(MaxNLocator(integer=True))
        bars.set_ylabel("trials that reached the goal")
        bars.set_title(f"{world}: successes")
        bars.legend(fontsize=8)
    figure.suptitle("Goal seeking: paths of the first trial (dotted: goal not reached)")
    header = ["world", "goal", "x,y (m)"] + [label for label, _ in goal_methods(goal_runs)]
    table = markdown("Figure 22: goal seeking, goals reached (mean time to goal)", header, body)
    note = "Share reached: each trial's share of the world's goals, mean ± 95 % interval.\n"
    return figure, table + "\n" + note
