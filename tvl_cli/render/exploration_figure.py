"""The exploration experiment's figure: coverage while learning by `tvl learn --explore`
rule, with its tables of coverage and time to competence."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from tvl_cli.analysis.aggregation import distinct, select
from tvl_cli.analysis.exploration import (
    COVERAGE_GOAL,
    COVERAGE_HEADER,
    collision_points,
    competence_rows,
    coverage_rows,
    mean_curve,
)
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.result_text import markdown
from tvl_cli.analysis.time_to_competence import competence_note
from tvl_cli.render.figure_parts import new_figure

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
