"""Figure 27's table: the behaviours in the lab against learning time, and the ends the paper
reports."""

from __future__ import annotations

from collections.abc import Sequence

from tvl_cli.analysis.aggregation import distinct, seed_interval, select
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.result_text import interval_text, method_label

# The paper's reported ends (SPEC §10) in the lab, multi FAM (§5.2, Fig. 27): learning minute
# -> mean speed m/s.
PAPER_FIG27 = {0.0: 0.1, 45.0: 0.5}


def learning_time_rows(
    snapshots: list[Row], series: Sequence[tuple[str, str, str]], dwa: list[Row]
) -> tuple[list[str], list[list[str]]]:
    """Figure 27's table: per learning minute, each (config, behaviour, method)'s mean speed
    and contacts a minute ± their 95 % intervals over the trials, then the DWA's avoid run
    as the last row."""

    def cell(runs: list[Row]) -> str:
        return (
            f"{interval_text(seed_interval(runs, 'mean_speed_mps'))}, "
            f"{interval_text(seed_interval(runs, 'contacts_per_min'))}"
        )

    header = ["minute"] + [f"{c} {b}, {method_label(m)}: m/s, contacts/min" for c, b, m in series]
    body = [
        [f"{minute:g}"]
        + [
            cell(select(snapshots, config=c, behaviour=b, method=m, minute=minute))
            for c, b, m in series
        ]
        for minute in distinct(snapshots, "minute")
    ]
    if dwa:
        body.append(["DWA (avoid)"] + [cell(dwa) if b == "avoid" else "–" for _, b, _ in series])
    return header, body
