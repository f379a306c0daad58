"""Learning while behaving (`tvl run --learn`): contacts a minute over the avoid runs, with
the FAM fixed and learning as it goes; with its summary table."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from tvl_cli.analysis.aggregation import distinct, mean, select
from tvl_cli.analysis.online_table import (
    ONLINE_HEADER,
    ONLINE_SETTINGS,
    minute_rates,
    online_conditions,
    online_rows,
)
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.result_text import markdown
from tvl_cli.analysis.wall_threshold import COLLISION_PRONE_PER_MIN
from tvl_cli.render.figure_parts import (
    CONFIG_STYLE,
    collision_axis,
    competence_limit,
    new_figure,
    shared_legend,
)


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
