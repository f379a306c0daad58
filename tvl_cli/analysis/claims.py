"""The paper's claims judged from a suite's rows (`tvl bench claims`): for each claim and
method, what was measured (means over the trials, with their 95 % interval where a figure is
a mean) and whether it meets what the paper reports.

A contact is a bump or a near miss, as in every metric here: where the paper counts
collisions, a near miss counts against the claim too.
"""

from __future__ import annotations

import statistics
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from tvl_cli.analysis.intervals import Interval, interval
from tvl_cli.analysis.wall_threshold import PAPER_FIG21
from tvl_cli.core.competence import MAX_CONTACTS_PER_MIN

Row = dict[str, Any]
# Each end of Figure 21 is met within this much (m, or m/s) of the paper's.
FIG21_TOLERANCE = 0.05
# Figure 27's end: the paper's 0.5 m/s, less a tenth.
FIG27_END_MPS = 0.45


@dataclass(frozen=True, slots=True)
class Verdict:
    measured: str
    met: bool


@dataclass(frozen=True, slots=True)
class Claim:
    name: str
    reported: str  # what the paper reports
    judge: Callable[[list[Row]], Verdict]  # from one method's rows of the claim


@dataclass(frozen=True, slots=True)
class ClaimRow:
    claim: str
    reported: str
    verdicts: dict[str, Verdict]  # by method

    def to_dict(self) -> dict[str, Any]:
        return {
            "claim": self.claim,
            "reported": self.reported,
            "verdicts": [
                {"method": m, "measured": v.measured, "met": v.met}
                for m, v in self.verdicts.items()
            ],
        }


def _text(found: Interval | None, digits: int = 2) -> str:
    if found is None:
        return "–"
    spread = "" if found.half_width is None else f" ± {found.half_width:.{digits}f}"
    return f"{found.mean:.{digits}f}{spread}"


def _by_seed(rows: list[Row], key: str) -> Interval | None:
    """The mean of `key` over each trial's rows, and its interval over the trials."""
    trials: dict[int, list[float]] = {}
    for row in rows:
        if row.get(key) is not None:
            trials.setdefault(row["seed"], []).append(float(row[key]))
    return interval([statistics.fmean(values) for values in trials.values()])


def avoid_9min(rows: list[Row]) -> Verdict:
    clean = sum(r["contacts_per_min"] <= MAX_CONTACTS_PER_MIN for r in rows)
    rate = _by_seed(rows, "contacts_per_min")
    text = f"{clean} of {len(rows)} runs clean, {_text(rate)} contacts/min"
    return Verdict(text, bool(rows) and clean == len(rows))


def fig21(rows: list[Row]) -> Verdict:
    low, high = sorted(PAPER_FIG21)
    ends = {t: [r for r in rows if r["threshold"] == t] for t in (low, high)}
    clear = {t: _by_seed(ends[t], "mean_wall_clearance_m") for t in ends}
    speed = {t: _by_seed(ends[t], "mean_speed_mps") for t in ends}
    contacts = _by_seed(rows, "contacts_per_min")
    text = (
        f"clearance {_text(clear[low])} → {_text(clear[high])} m, speed {_text(speed[low])} → "
        f"{_text(speed[high])} m/s, {_text(contacts, 1)} contacts/min"
    )
    met = all(
        (c := clear[t]) is not None
        and (v := speed[t]) is not None
        and abs(c.mean - reported_c) <= FIG21_TOLERANCE
        and abs(v.mean - reported_v) <= FIG21_TOLERANCE
        for t, (reported_c, reported_v) in PAPER_FIG21.items()
    )
    return Verdict(text, met)


def fig22(rows: list[Row]) -> Verdict:
    # A run that reaches its goal only grazing on the way counts against the claim.
    found = sum(bool(r["goal_reached"]) and r["contacts"] == 0 for r in rows)
    reached = sum(bool(r["goal_reached"]) for r in rows)
    goals = len({r["goal"] for r in rows})
    text = f"{found} of {len(rows)} goals found without contacts ({reached} reached)"
    return Verdict(text, bool(rows) and found >= len(rows) * (goals - 1) / goals)


def fig24(rows: list[Row]) -> Verdict:
    configs = {name: [r for r in rows if r["config"] == name] for name in ("single", "multi")}
    rates = {name: _by_seed(runs, "contacts_per_min") for name, runs in configs.items()}
    bumps = {name: _by_seed(runs, "collisions_per_min") for name, runs in configs.items()}
    text = (
        f"contacts/min single {_text(rates['single'])}, multi {_text(rates['multi'])} (bumps "
        f"alone {_text(bumps['single'])}, {_text(bumps['multi'])})"
    )
    # Both clean leaves nothing for the multi FAM to improve on: the claim is not shown.
    met = (
        rates["single"] is not None
        and rates["multi"] is not None
        and rates["multi"].mean < rates["single"].mean
    )
    return Verdict(text, met)


def fig27(rows: list[Row]) -> Verdict:
    minutes = sorted({r["minute"] for r in rows})
    speeds = [_by_seed([r for r in rows if r["minute"] == m], "mean_speed_mps") for m in minutes]
    text = "avoid speed " + ", ".join(
        f"{_text(v)} m/s at {m:g} min" for m, v in zip(minutes, speeds, strict=True)
    )
    last = speeds[-1] if speeds else None
    return Verdict(text, last is not None and last.mean >= FIG27_END_MPS)


CLAIMS: dict[str, Claim] = {
    claim.name: claim
    for claim in (
        Claim("avoid-9min", "square and circle avoided without collisions", avoid_9min),
        Claim("fig21", "clearance 0.32 → 0.67 m, speed 0.32 → 0.45 m/s", fig21),
        Claim("fig22", "every goal found without collisions but one", fig22),
        Claim("fig24", "multi collides less than single", fig24),
        Claim("fig27", "avoid speed 0.1 → 0.5 m/s over 45 min", fig27),
    )
}


def judge(rows: Sequence[Row], claims: Sequence[str], methods: Sequence[str]) -> list[ClaimRow]:
    """Each claim's verdict for each method, from the rows tagged with it."""
    return [
        ClaimRow(
            name,
            CLAIMS[name].reported,
            {
                method: CLAIMS[name].judge(
                    [r for r in rows if r["claim"] == name and r["method"] == method]
                )
                for method in methods
            },
        )
        for name in claims
    ]
