"""The reflex ablation's figure: contacts a minute with each reflex setting, per world and
behaviour; with its summary tables."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from tvl_cli.analysis.ablation_table import (
    ABLATION_HEADER,
    ABLATION_SETTINGS,
    ablation_rows,
    ablation_setting,
)
from tvl_cli.analysis.aggregation import distinct, mean, select
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.result_text import WORLD_ORDER, markdown
from tvl_cli.analysis.time_to_competence import competence_note
from tvl_cli.analysis.wall_threshold import COLLISION_PRONE_PER_MIN
from tvl_cli.render.figure_parts import (
    CONFIG_STYLE,
    collision_axis,
    competence_limit,
    new_figure,
    shared_legend,
)


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
