"""The figures against learning time (paper §5): learning curves and competence (Figure 19),
single against multi FAM (Figure 24) and the behaviours in the lab (Figure 27); each also
returns its summary table."""

from __future__ import annotations

from matplotlib.figure import Figure

from tvl_cli.analysis.aggregation import distinct, learning_minutes, mean, select
from tvl_cli.analysis.learning_time_table import PAPER_FIG27, learning_time_rows
from tvl_cli.analysis.method_table import METHOD_HEADER, METHOD_NOTE, method_rows
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.result_text import WORLD_ORDER, markdown, method_label, methods_of
from tvl_cli.analysis.time_to_competence import (
    competence_note,
    competence_times,
    describe_competence,
)
from tvl_cli.core.method import DEFAULT_NAME
from tvl_cli.render.figure_parts import (
    CONFIG_STYLE,
    DWA_COLOUR,
    OTHER_METHOD_ALPHA,
    PAPER_COLOUR,
    QLEARN_COLOUR,
    band_curve,
    baselines_and_limits,
    collision_axis,
    competence_bar,
    method_line,
    new_figure,
    reference_line,
    shared_legend,
)

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
