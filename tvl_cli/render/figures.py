"""The experiment figures (paper §5), drawn from the numbers analysis.results computes out
of a sweep's rows; each figure also returns its summary table."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from itertools import pairwise
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from tvl_cli.analysis.exploration import (
    COVERAGE_GOAL,
    COVERAGE_HEADER,
    collision_points,
    competence_rows,
    coverage_rows,
    mean_curve,
)
from tvl_cli.analysis.intervals import Interval
from tvl_cli.analysis.results import (
    ABLATION_HEADER,
    ABLATION_SETTINGS,
    COLLISION_PRONE_PER_MIN,
    METHOD_HEADER,
    METHOD_NOTE,
    ONLINE_HEADER,
    ONLINE_SETTINGS,
    PAPER_FIG21,
    PAPER_FIG27,
    WORLD_ORDER,
    Row,
    ablation_rows,
    ablation_setting,
    competence_note,
    competence_times,
    curve,
    curve_band,
    describe_competence,
    distinct,
    goal_methods,
    interval_text,
    learning_minutes,
    learning_time_rows,
    markdown,
    mean,
    method_label,
    method_rows,
    methods_of,
    minute_rates,
    number,
    online_conditions,
    online_rows,
    prone,
    qlearn_checks,
    seed_interval,
    select,
    threshold_points,
)
from tvl_cli.core import competence
from tvl_cli.core.method import DEFAULT_NAME, PAPER_NAME
from tvl_cli.render.plot import draw_world
from tvl_cli.sim.worldmap import parse_world

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


# --- Figure 19: learning curves ------------------------------------------------------


def figure19(rows: list[Row]) -> tuple[Figure, str]:
    worlds = distinct(select(rows, kind="learn"), "world", WORLD_ORDER)
    figure = new_figure(4.2 * len(worlds), 10)
    axes = figure.subplots(4, len(worlds), sharex="col", squeeze=False)
    for column, world in enumerate(worlds):
        dv, learn_hits, hits, speed = axes[:, column]
        for index, method in enumerate(methods_of(select(rows, world=world))):
            by_method = select(rows, world=world, method=method)
            learnt = learning_minutes(by_method)
            snapshots = select(by_method, kind="tvl", behaviour="avoid")
            line, colour = f"o{method_line(method)}", f"C{index}"
            label = f"TVL, {method_label(method)}"
            band_curve(dv, learnt, "minute", "delta_v", line, colour, label)
            band_curve(learn_hits, learnt, "minute", "collisions", line, colour, label)
            band_curve(hits, snapshots, "minute", "contacts_per_min", line, colour, label)
            band_curve(speed, snapshots, "minute", "mean_speed_mps", line, colour, label)
            times = [t for t in competence_times(snapshots) if t is not None]
            if times:
                for ax in (hits, speed):
                    ax.axvline(
                        mean(times),
                        color=colour,
                        linestyle=method_line(method),
                        linewidth=0.8,
                        label=f"competent, {method_label(method)}",
                    )
        dv.set_title(world)
        learn_hits.set_ylim(bottom=0)
        baselines_and_limits(hits, speed, rows, world)
        speed.set_xlabel("learning time (simulated min)")
        for ax in axes[:, column]:
            ax.grid(alpha=0.3)
    axes[0, 0].set_ylabel("ΔV (m/s per step)")
    axes[1, 0].set_ylabel("collisions/min, learning")
    axes[2, 0].set_ylabel("contacts/min, avoid run")
    axes[3, 0].set_ylabel("mean speed (m/s), avoid run")
    shared_legend(figure, axes.flat)
    figure.suptitle(
        "Learning curves and competence, single FAM (mean and 95 % interval over trials)"
    )
    body = [cells for world in worlds for cells in method_rows(rows, world, ["single"])]
    table = markdown("Figure 19: learning and competence", METHOD_HEADER, body)
    return figure, table + "\n" + METHOD_NOTE + competence_note(rows)


# --- Figure 21: velocity threshold ---------------------------------------------------


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


# --- Figure 22: goal seeking ---------------------------------------------------------


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


# --- Figure 24: single against multi FAM ---------------------------------------------


def figure24(rows: list[Row]) -> tuple[Figure, str]:
    snapshots = select(rows, kind="tvl", behaviour="avoid")
    worlds = distinct(snapshots, "world", WORLD_ORDER)
    configs = distinct(snapshots, "config", ("single", "multi"))
    series = [(c, m) for m in methods_of(snapshots) for c in configs]
    figure = new_figure(max(5 * len(worlds), 8), 9)
    axes = figure.subplots(3, len(worlds), squeeze=False)
    for column, world in enumerate(worlds):
        hits, speed, bars = axes[:, column]
        labels: list[str] = []
        # ((height, hatch), colour, opacity): the paper's method's bars paler than ours
        bars_of: list[tuple[tuple[float, str], str, float]] = []
        horizon = max(r["minute"] for r in select(snapshots, world=world))
        for config, method in series:
            runs = select(snapshots, world=world, config=config, method=method)
            if not runs:
                continue
            colour = CONFIG_STYLE.get(config, "black")
            label = f"TVL {config}, {method_label(method)}"
            line = f"o{method_line(method)}"
            band_curve(hits, runs, "minute", "contacts_per_min", line, colour, label)
            band_curve(speed, runs, "minute", "mean_speed_mps", line, colour, label)
            labels.append(f"{config}\n{method_label(method)}")
            opacity = 1.0 if method == DEFAULT_NAME else OTHER_METHOD_ALPHA
            bars_of.append((competence_bar(competence_times(runs), horizon), colour, opacity))
        baselines_and_limits(hits, speed, rows, world)
        qlearn = select(rows, kind="qlearn", world=world)
        if qlearn:
            times = [r.get("time_to_competence_min") for r in qlearn]
            labels.append("Q-learning")
            q_horizon = max(r["learn_minutes"] for r in qlearn)
            bars_of.append((competence_bar(times, q_horizon), QLEARN_COLOUR, 1.0))
        for x, ((height, hatch), colour, opacity) in enumerate(bars_of):
            bars.bar(x, height, color=colour, alpha=opacity, hatch=hatch, edgecolor="black")
        bars.set_xticks(range(len(labels)), labels, fontsize=7)
        bars.set_ylabel("time to competence (min)")
        bars.set_title("hatched: some trials not competent (bar: horizon)", fontsize=8)
        hits.set_title(world)
        hits.set_ylabel("contacts/min, avoid run")
        speed.set_ylabel("mean speed (m/s), avoid run")
        speed.set_xlabel("learning time (simulated min)")
        for ax in (hits, speed):
            ax.grid(alpha=0.3)
    shared_legend(figure, axes.flat)
    figure.suptitle(
        "Single against multi FAM, trained from the same logs (mean and 95 % interval over trials)"
    )
    body = [cells for world in worlds for cells in method_rows(rows, world, configs)]
    table = markdown("Figure 24: single against multi FAM", METHOD_HEADER, body)
    return figure, table + "\n" + METHOD_NOTE + competence_note(rows)


# --- Figure 27: the lab ----------------------------------------------------------------

BEHAVIOUR_MARKERS = {"avoid": "o", "wall": "s"}


def figure27(rows: list[Row]) -> tuple[Figure, str]:
    snapshots = select(rows, kind="tvl")
    configs = distinct(snapshots, "config", ("single", "multi"))
    behaviours = distinct(snapshots, "behaviour", ("avoid", "wall"))
    methods = methods_of(snapshots)
    series = [(c, b, m) for m in methods for c in configs for b in behaviours]
    figure = new_figure(11, 4.8)
    speed, hits = figure.subplots(1, 2)
    for config, behaviour, method in series:
        runs = select(snapshots, config=config, behaviour=behaviour, method=method)
        if not runs:
            continue
        style = BEHAVIOUR_MARKERS.get(behaviour, "^") + method_line(method)
        colour = CONFIG_STYLE.get(config, "black")
        label = f"{config} FAM, {behaviour}, {method_label(method)}"
        band_curve(speed, runs, "minute", "mean_speed_mps", style, colour, label)
        band_curve(hits, runs, "minute", "contacts_per_min", style, colour, label)
    minutes = sorted(PAPER_FIG27)
    speed.plot(
        minutes,
        [PAPER_FIG27[m] for m in minutes],
        "x:",
        color=PAPER_COLOUR,
        label="paper, multi FAM (ends only)",
    )
    dwa = select(rows, kind="dwa", behaviour="avoid")
    reference_line(speed, mean(r["mean_speed_mps"] for r in dwa), DWA_COLOUR, "DWA avoid")
    reference_line(hits, mean(r["contacts_per_min"] for r in dwa), DWA_COLOUR, "DWA avoid")
    collision_axis(hits)
    speed.set_ylabel("mean speed (m/s)")
    hits.set_ylabel("contacts/min")
    for ax in (speed, hits):
        ax.set_xlabel("learning time (simulated min)")
        ax.grid(alpha=0.3)
    shared_legend(figure, [speed])
    world = "/".join(distinct(snapshots, "world", WORLD_ORDER))
    figure.suptitle(
        f"Behaviours in {world} against learning time (mean and 95 % interval over trials)"
    )
    header, body = learning_time_rows(snapshots, series, dwa)
    table = markdown(f"Figure 27: behaviours in {world} against learning time", header, body)
    times = [
        f"- {config} FAM, {method_label(method)}: time to competence "
        + describe_competence(
            competence_times(select(snapshots, config=config, behaviour="avoid", method=method)),
            max(r["minute"] for r in snapshots),
        )
        for method in methods
        for config in configs
    ]
    (start, start_mps), (end, end_mps) = sorted(PAPER_FIG27.items())
    paper = (
        f"Paper (§5.2): multi FAM mean speed {start_mps:g} → {end_mps:g} m/s "
        f"from minute {start:g} to {end:g} of learning. Cells: mean ± 95 % interval over "
        "trials.\n"
    )
    return figure, table + "\n" + "\n".join(times) + "\n\n" + paper + competence_note(rows)


def ablation(rows: list[Row]) -> tuple[Figure, str]:
    """Contacts a minute and speed with each reflex setting, per world and behaviour."""
    behaviours = distinct(select(rows, kind="tvl"), "behaviour", ("avoid", "wall-left"))
    worlds = distinct(select(rows, kind="tvl"), "world", WORLD_ORDER)
    figure = new_figure(4.0 * len(worlds), 3.2 * len(behaviours))
    grid = figure.subplots(len(behaviours), len(worlds), squeeze=False)
    settings = list(ABLATION_SETTINGS)
    x = np.arange(len(settings))
    width = 0.4
    for row_axes, behaviour in zip(grid, behaviours, strict=True):
        for ax, world in zip(row_axes, worlds, strict=True):
            for offset, config in ((-width / 2, "single"), (width / 2, "multi")):
                runs = select(rows, kind="tvl", behaviour=behaviour, world=world, config=config)
                values = [
                    mean(r["contacts_per_min"] for r in runs if ablation_setting(r) == s)
                    for s in settings
                ]
                heights = [np.nan if v is None else v for v in values]
                ax.bar(x + offset, heights, width, color=CONFIG_STYLE[config], label=config)
            competence_limit(ax, COLLISION_PRONE_PER_MIN)
            collision_axis(ax)
            ax.set_title(f"{behaviour} in {world}", fontsize=9)
            ax.set_xticks(x, settings, rotation=45, ha="right", fontsize=7)
        row_axes[0].set_ylabel("contacts/min")
    shared_legend(figure, [grid[0][0]])
    figure.suptitle("Reflex ablation: each reflex alone, all, none, and the paper's method")
    tables = [
        markdown(f"{behaviour}: reflex ablation", ABLATION_HEADER, ablation_rows(rows, behaviour))
        for behaviour in behaviours
    ]
    note = (
        "Reflexes: `none` is the paper's choice rule alone on a FAM learnt with our defaults; "
        "`paper` is the paper's whole method (its labels, bump-only collision points, no "
        "reflexes). Contacts are collisions and near misses; means over trials.\n"
    )
    return figure, "\n".join(tables) + "\n" + note + competence_note(rows)


def online(rows: list[Row]) -> tuple[Figure, str]:
    """Contacts a minute over behaving runs, with the FAM fixed and learning as it goes, for
    each length of exploration before them."""
    conditions = online_conditions(rows)
    figure = new_figure(3.6 * len(conditions), 3.4)
    axes = figure.subplots(1, len(conditions), squeeze=False)[0]
    styles = {False: ("s--", "grey"), True: ("o-", CONFIG_STYLE["single"])}
    for ax, (start, threshold) in zip(axes, conditions, strict=True):
        for setting, label in ONLINE_SETTINGS.items():
            runs = select(rows, kind="tvl", online=setting, minute=start, threshold=threshold)
            rates = [minute_rates(r) for r in runs]
            longest = max((len(r) for r in rates), default=0)
            minutes = np.arange(1, longest + 1)
            means = [mean(r[k] for r in rates if k < len(r)) for k in range(longest)]
            style, colour = styles[setting]
            ax.plot(minutes, means, style, ms=3, color=colour, label=f"FAM {label}")
        competence_limit(ax, COLLISION_PRONE_PER_MIN)
        collision_axis(ax)
        ax.set_title(f"after {start:g} min exploring, threshold {threshold:g}", fontsize=9)
        ax.set_xlabel("minute of the avoid run")
        ax.grid(alpha=0.3)
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    axes[0].set_ylabel("contacts/min (mean of runs)")
    shared_legend(figure, axes[:1])
    worlds = ", ".join(distinct(select(rows, kind="tvl"), "world"))
    figure.suptitle(f"Learning while behaving (tvl run --learn): avoid in {worlds}")
    table = markdown("Learning while behaving: avoid", ONLINE_HEADER, online_rows(rows))
    note = (
        "Each run starts from a FAM trained on the first minutes of an exploratory learning "
        "log (0: nothing learnt, every entry at its initial velocity) and drives avoid with "
        "every reflex; `learns` trains that FAM on what the run meets (`tvl run --learn`). "
        "Contacts are collisions and near misses; means over worlds and seeds.\n"
    )
    return figure, table + "\n" + note


# --- Exploration strategies: coverage and time to competence --------------------------

RULE_COLOURS = {"least-experience": "#1f77b4", "novelty": "#d62728", "random": "#2ca02c"}


def exploration(rows: list[Row]) -> tuple[Figure, str]:
    """Coverage against learning time for each `tvl learn --explore` rule, in the lab and
    over the other worlds; the time to competence each rule's FAM took."""
    learnt = select(rows, kind="learn")
    others = tuple(w for w in distinct(learnt, "world") if w != "lab")
    groups = [
        (title, worlds)
        for title, worlds in (("lab", ("lab",)), (", ".join(others), others))
        if select(learnt, world=worlds)
    ]
    figure = new_figure(5.0 * len(groups), 4.0)
    axes = figure.subplots(1, len(groups), squeeze=False)[0]
    styles = {"sonar": "-", "bumps": "--"}
    for ax, (title, worlds) in zip(axes, groups, strict=True):
        here = select(learnt, world=worlds)
        for near_m in distinct(here, "near_m"):
            points = collision_points(near_m)
            for rule in distinct(here, "exploration"):
                curve_ = mean_curve(select(here, near_m=near_m, exploration=rule))
                label = rule if points == "sonar" else f"{rule}, bumps only (--near 0)"
                ax.plot(
                    np.arange(1, len(curve_) + 1),
                    100 * curve_,
                    styles.get(points, ":"),
                    color=RULE_COLOURS.get(rule, "black"),
                    label=label,
                )
        ax.axhline(100 * COVERAGE_GOAL, color="grey", linestyle=":", linewidth=1, label="goal")
        ax.set_ylim(0, 100)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("learning minute")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("coverage (%, mean of trials)")
    # Every panel draws the rules in the same colours: one legend, where the lab's curves
    # leave room.
    axes[0].legend(fontsize=7, loc="lower right")
    figure.suptitle("Coverage while learning, by tvl learn --explore rule")
    tables = [
        markdown(f"Coverage while learning: {title}", COVERAGE_HEADER, coverage_rows(rows, worlds))
        for title, worlds in groups
    ]
    header, body = competence_rows(rows)
    tables.append(markdown("Time to competence (avoid), min (trials)", header, body))
    note = (
        "Coverage: the fraction of the world map's cells that a body of the robot's radius can "
        "reach from the start whose cell the robot's centre has passed, from the true poses "
        "in the log. Collision points: `sonar` is the learner's default, `bumps` learns with "
        "--near 0. Time to competence is read at the lengths of learning tried (snapshots "
        "of each log): the shortest whose FAM made avoid competent.\n"
    )
    return figure, "\n".join(tables) + "\n" + note + competence_note(rows)


# --- the registry -----------------------------------------------------------------------

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
