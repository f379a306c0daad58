"""The reflex ablation's numbers (experiments/grids/ablation.toml): its settings in order,
each run's place among them, and its table of contacts, speed, spins and back-offs."""

from __future__ import annotations

from tvl_cli.analysis.aggregation import distinct, mean, seed_interval, select
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.result_text import WORLD_ORDER, interval_text, number
from tvl_cli.analysis.time_to_competence import is_competent
from tvl_cli.core.method import PAPER_NAME

# The ablation's settings in table order: the policy alone, each reflex alone, all of them,
# and the paper's whole method (its labels and collision points too).
ABLATION_SETTINGS = (
    "none", "blocked-ways", "near-miss", "bump", "tie", "wall-start", "all", "paper",
)  # fmt: skip


def ablation_setting(run: Row) -> str:
    """A TVL run's place in the ablation: its reflexes, or "paper" for the paper's method."""
    return PAPER_NAME if run["method"] == PAPER_NAME else str(run["reflexes"])


def per_min(runs: list[Row], key: str) -> float | None:
    """The mean over runs of a count per simulated minute."""
    return mean(r[key] / (r["sim_s"] / 60.0) for r in runs if r["sim_s"])


def ablation_rows(rows: list[Row], behaviour: str) -> list[list[str]]:
    """One table row per world, configuration and setting: contacts (collisions + near
    misses), speed overall and while driving, spins and back-offs a minute, and for avoid
    how many trials were competent."""
    table: list[list[str]] = []
    runs_of = select(rows, kind="tvl", behaviour=behaviour)
    for world in distinct(runs_of, "world", WORLD_ORDER):
        for config in distinct(select(runs_of, world=world), "config", ("single", "multi")):
            for setting in ABLATION_SETTINGS:
                runs = [
                    r
                    for r in select(runs_of, world=world, config=config)
                    if ablation_setting(r) == setting
                ]
                if not runs:
                    continue
                competent = sum(is_competent(r) for r in runs)
                table.append(
                    [
                        world,
                        config,
                        setting,
                        interval_text(seed_interval(runs, "contacts_per_min")),
                        f"{number(per_min(runs, 'collisions'))} + "
                        f"{number(per_min(runs, 'near_misses'))}",
                        interval_text(seed_interval(runs, "mean_speed_mps")),
                        number(mean(r["mean_drive_speed_mps"] for r in runs)),
                        number(per_min(runs, "spins"), 1),
                        number(per_min(runs, "backoffs"), 1),
                        f"{competent}/{len(runs)}" if behaviour == "avoid" else "–",
                    ]
                )
    return table


ABLATION_HEADER = (
    "world",
    "FAM",
    "reflexes",
    "contacts/min",
    "collisions + near misses /min",
    "speed m/s",
    "driving m/s",
    "spins/min",
    "back-offs/min",
    "competent",
)
