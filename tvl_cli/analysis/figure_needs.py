"""What each figure draws from, checked before it is drawn: runs of the kinds it reads, with
the keys it reads and something to plot, else BadInput naming what is missing."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from tvl_cli.analysis.ablation_table import ABLATION_SETTINGS
from tvl_cli.analysis.aggregation import select
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.wall_threshold import WALL_BEHAVIOURS
from tvl_cli.core.errors import BadInput


@dataclass(frozen=True, slots=True)
class Needs:
    """What a figure draws from: runs of a kind (with these values; a tuple: any of them),
    having these keys, and for each key it plots a value (not null, not empty) in at least one
    of them, else its panel would be empty."""

    what: str
    where: dict[str, Any]
    keys: tuple[str, ...]
    plotted: tuple[str, ...]


_RUN_KEYS = ("world", "seed", "contacts_per_min", "mean_speed_mps")
_PLOTTED = ("contacts_per_min", "mean_speed_mps")
FIGURE_NEEDS: dict[str, tuple[Needs, ...]] = {
    "fig19": (
        Needs("learning runs", {"kind": "learn"}, ("world", "seed", "minutes"), ("minutes",)),
        Needs(
            "avoid snapshots",
            {"kind": "tvl", "behaviour": "avoid"},
            (*_RUN_KEYS, "minute"),
            _PLOTTED,
        ),
    ),
    "fig21": (
        Needs(
            "wall runs",
            {"kind": "tvl", "behaviour": WALL_BEHAVIOURS},
            (*_RUN_KEYS, "threshold", "mean_wall_clearance_m"),
            ("mean_wall_clearance_m", "mean_speed_mps"),
        ),
    ),
    "fig22": (Needs("goal runs", {"behaviour": "goal"}, ("world", "seed", "goal_reached"), ()),),
    "fig24": (
        Needs(
            "avoid snapshots",
            {"kind": "tvl", "behaviour": "avoid"},
            (*_RUN_KEYS, "minute"),
            _PLOTTED,
        ),
    ),
    "fig27": (Needs("snapshots", {"kind": "tvl"}, (*_RUN_KEYS, "config", "minute"), _PLOTTED),),
    "ablation": (
        Needs(
            "runs",
            {"kind": "tvl", "reflexes": ABLATION_SETTINGS},
            (*_RUN_KEYS, "config", "method"),
            ("contacts_per_min",),
        ),
    ),
    "online": (
        Needs(
            "behaving runs",
            {"kind": "tvl"},
            (*_RUN_KEYS, "online", "minute", "threshold", "minutes"),
            ("minutes",),
        ),
    ),
    "exploration": (
        Needs(
            "learning runs",
            {"kind": "learn"},
            ("world", "seed", "exploration", "near_m", "minutes"),
            ("minutes",),
        ),
        Needs(
            "avoid snapshots",
            {"kind": "tvl", "behaviour": "avoid"},
            (*_RUN_KEYS, "exploration", "minute"),
            _PLOTTED,
        ),
    ),
}


def check_needs(name: str, rows: dict[int, Row], source: str) -> None:
    """BadInput unless the rows (by line number) hold the runs figure NAME draws, with the keys
    it reads and something to plot."""
    for needs in FIGURE_NEEDS[name]:
        runs = select(rows.values(), **needs.where)
        kinds = ", ".join(f"{k} {_alternatives(v)}" for k, v in needs.where.items())
        if not runs:
            raise BadInput(f"{source}: no {needs.what} ({kinds}) for {name}")
        for run in runs:
            missing = [key for key in needs.keys if key not in run]
            if missing:
                raise BadInput(
                    f"{source}: a run ({kinds}) lacks the key {missing[0]!r} that {name} needs"
                )
        for key in needs.plotted:
            if not any(run[key] not in (None, []) for run in runs):
                raise BadInput(f"{source}: no {needs.what} ({kinds}) with a {key!r} for {name}")


def _alternatives(value: Any) -> str:
    return "/".join(map(str, value)) if isinstance(value, tuple) else str(value)
