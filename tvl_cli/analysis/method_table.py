"""Figures 19 and 24's table: TVL's configurations by each method beside DWA and Q-learning
in a world: time to competence, an avoid run's contacts, speed and clearance, and the
collisions while learning."""

from __future__ import annotations

from collections.abc import Sequence

from tvl_cli.analysis.aggregation import by_trial, final_runs, learning_minutes, mean, select
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.result_text import method_label, methods_of, spread
from tvl_cli.analysis.time_to_competence import competence_times, describe_competence


def method_rows(rows: list[Row], world: str, configs: Sequence[str]) -> list[list[str]]:
    """Table rows for TVL's configurations by each method, DWA and Q-learning in one world:
    time to competence, collision rate, speed and clearance of an avoid run (each trial's
    last; mean ± 95 % interval over trials), collisions in learning."""
    table: list[list[str]] = []
    for method in methods_of(select(rows, world=world)):
        by_method = select(rows, world=world, method=method)
        learnt = learning_minutes(by_method)
        horizon = max((m["minute"] for m in learnt), default=None)
        for config in configs:
            snapshots = select(by_method, kind="tvl", config=config, behaviour="avoid")
            if not snapshots:
                continue
            last = final_runs(snapshots)
            horizon = horizon or max(r["minute"] for r in snapshots)
            table.append(
                [
                    world,
                    f"TVL {config} FAM, {method_label(method)}",
                    describe_competence(competence_times(snapshots), horizon),
                    spread(r["contacts_per_min"] for r in last),
                    spread(r["mean_speed_mps"] for r in last),
                    spread(r["mean_clearance_m"] for r in last),
                    spread(_learning_rates(learnt)),
                ]
            )
    dwa = select(rows, kind="dwa", world=world, behaviour="avoid")
    if dwa:
        table.append(
            [
                world,
                "DWA (knows the map)",
                "no learning",
                spread(r["contacts_per_min"] for r in dwa),
                spread(r["mean_speed_mps"] for r in dwa),
                spread(r["mean_clearance_m"] for r in dwa),
                "–",
            ]
        )
    qlearn = select(rows, kind="qlearn", world=world)
    if qlearn:
        times = [r.get("time_to_competence_min") for r in qlearn]
        table.append(
            [
                world,
                "Q-learning",
                describe_competence(times, max(r["learn_minutes"] for r in qlearn)),
                spread(r["contacts_per_min"] for r in qlearn),
                spread(r["mean_speed_mps"] for r in qlearn),
                spread(r["mean_clearance_m"] for r in qlearn),
                spread(r["learn_collisions"] / r["learn_minutes"] for r in qlearn),
            ]
        )
    return table


def _learning_rates(learnt: list[Row]) -> list[float | None]:
    """Each trial's collisions a minute while learning."""
    return [mean(m["collisions"] for m in minutes) for minutes in by_trial(learnt).values()]


METHOD_HEADER = (
    "world",
    "method",
    "time to competence, min (trials)",
    "avoid contacts/min",
    "avoid speed m/s",
    "avoid clearance m",
    "collisions/min learning",
)
METHOD_NOTE = (
    "Avoid columns: the FAM at the end of learning (Q-learning: its greedy policy); "
    "mean ± 95 % interval over trials (Student's t; the mean alone from one trial). "
    "Ours is the default method; the paper's is `--method paper`.\n"
)
