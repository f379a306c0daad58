"""The experiments' numbers: result rows (one JSON line per run) into competence times,
means and summary tables. No drawing: render.figures draws from these.

Each line of a results file is one run: its parameters (`kind`: learn, tvl, dwa or qlearn;
`world`, `seed`, `config`, `minute`, `behaviour`, `threshold`, `reflexes`, ...) and what
`tvl ... --json` printed. Trials are the seeds; figures show their mean, tables their mean
and counts.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.core import competence, jsontext
from tvl_cli.core.errors import BadInput
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.trajectory_choice import BEHAVIOUR_NAMES, is_threshold

Row = dict[str, Any]

# A setting is collision prone above the competence limit (dashed in Figure 21).
COLLISION_PRONE_PER_MIN = competence.MAX_CONTACTS_PER_MIN

WORLD_ORDER = ("square", "circle", "corridor", "obstacles", "narrow", "lab")
# The ablation's settings in table order: the policy alone, each reflex alone, all of them,
# and the paper's whole method (its labels and collision points too).
ABLATION_SETTINGS = (
    "none", "blocked-ways", "near-miss", "bump", "tie", "wall-start", "all", "paper",
)  # fmt: skip
# The online experiment's runs: the FAM fixed, or learning while behaving (`tvl run --learn`).
ONLINE_SETTINGS = ("fixed", "learns")
# The paper's reported ends (SPEC §10): threshold -> (wall clearance m, mean speed m/s) in
# wall following (§5.1, Fig. 21), and learning minute -> mean speed m/s in the lab, multi FAM
# (§5.2, Fig. 27).
PAPER_FIG21 = {0.65: (0.32, 0.32), 0.95: (0.67, 0.45)}
PAPER_FIG27 = {0.0: 0.1, 45.0: 0.5}


def is_competent(run: Row) -> bool:
    """Whether an avoid run (its `tvl run --json` keys) passes the competence test."""
    return competence.is_competent(RunMetrics(**{f.name: run[f.name] for f in fields(RunMetrics)}))


def time_to_competence(snapshots: Iterable[Row]) -> float | None:
    """Time to competence: the first learning minute whose snapshot FAM's avoid run is
    competent; None if none is."""
    competent = [row["minute"] for row in snapshots if is_competent(row)]
    return min(competent) if competent else None


# --- reading and summarising -------------------------------------------------------


def read_results(path: Path) -> dict[int, Row]:
    """The runs of a JSON-lines results file by line number; BadInput naming the line that is
    not one."""
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise BadInput(f"{path}: no such results file") from None
    except (OSError, UnicodeDecodeError) as error:
        raise BadInput(f"{path}: cannot read ({error})") from None
    rows: dict[int, Row] = {}
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip():
            continue
        where = f"{path}:{number}"
        try:
            row = jsontext.loads(line, where, "a run")
        except json.JSONDecodeError as error:
            raise BadInput(f"{where}:{error.colno}: not JSON ({error.msg})") from None
        if not isinstance(row, dict) or not isinstance(row.get("kind"), str):
            raise BadInput(f'{where}: not a run (an object with a "kind")')
        _check_types(row, where)
        rows[number] = row
    return rows


# The keys the figures read, by what they must hold. Parameters and measures are numbers
# (finite: json reads NaN and Infinity, which would show as "–"); only the measures a run may
# not have taken can be null. `minutes` (a learn run's) and `competence_checks` (Q-learning's)
# are lists of objects whose keys are checked as a run's are.
_WORDS = (
    "world",
    "config",
    "behaviour",
    "reflexes",
    "learning",
    "goal",
    "online",
    "explore",
    "collision_points",
)
_NUMBERS = (
    "seed",
    "minute",
    "start_minutes",
    "learnt_minutes",
    "coverage",
    "threshold",
    "learn_minutes",
    "run_minutes",
    "goal_index",
    "delta_v",
    "learn_collisions",
    *(f.name for f in fields(RunMetrics) if f.name != "goal_reached"),
)
_MAYBE_TAKEN = ("mean_wall_clearance_m", "time_to_goal_s", "time_to_competence_min")
# A `tvl sweep` row records a goal for every run, null for those that seek none.
_MAYBE_NAMED = ("goal",)
_FLAGS = ("goal_reached",)
_LISTS = ("minutes", "competence_checks")


def _check_types(row: Row, where: str) -> None:
    """BadInput naming the first key a figure reads that does not hold what it names."""
    for key in _WORDS:
        if key in row and not isinstance(row[key], str):
            if row[key] is None and key in _MAYBE_NAMED:
                continue
            raise BadInput(f"{where}: {key!r} is {row[key]!r}, expected text")
    for key in (*_NUMBERS, *_MAYBE_TAKEN):
        value = row.get(key)
        if key not in row or (value is None and key in _MAYBE_TAKEN):
            continue
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            raise BadInput(f"{where}: {key!r} is {value!r}, expected a number")
    for key in _FLAGS:
        if key in row and not isinstance(row[key], bool):
            raise BadInput(f"{where}: {key!r} is {row[key]!r}, expected true or false")
    if "threshold" in row and not is_threshold(row["threshold"]):
        raise BadInput(f"{where}: 'threshold' is {row['threshold']!r}, outside (0, 1]")
    for key in _LISTS:
        items = row.get(key, [])
        if not isinstance(items, list):
            raise BadInput(f"{where}: {key!r} is {items!r}, expected a list of objects")
        for index, item in enumerate(items, start=1):
            at = f"{where}: {key!r} item {index}"
            if not isinstance(item, dict):
                raise BadInput(f"{at} is {item!r}, expected an object")
            _check_types(item, at)


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
WALL_BEHAVIOURS = tuple(name for name in BEHAVIOUR_NAMES if name.startswith("wall"))
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
            (*_RUN_KEYS, "config"),
            ("contacts_per_min",),
        ),
    ),
    "online": (
        Needs(
            "behaving runs",
            {"kind": "tvl", "online": ONLINE_SETTINGS},
            (*_RUN_KEYS, "start_minutes", "threshold", "minutes"),
            ("minutes",),
        ),
    ),
    "exploration": (
        Needs(
            "learning runs",
            {"kind": "learn"},
            ("world", "seed", "explore", "collision_points", "minutes"),
            ("minutes",),
        ),
        Needs(
            "avoid snapshots",
            {"kind": "tvl", "behaviour": "avoid"},
            (*_RUN_KEYS, "explore", "learnt_minutes"),
            _PLOTTED,
        ),
    ),
}
# Each experiment script marks its TVL runs with a key no other one records: the learning
# `minute` of a snapshot FAM, the ablation's `learning`, fig22's `goal_index`, the online
# experiment's `start_minutes` (of exploration before behaving), the exploration
# experiment's `explore` (the rule that chose where to learn); fig21's
# threshold runs have none. A figure refuses the TVL runs of another experiment, which it
# would otherwise average in silently (the ablation would average over fig21's thresholds).
FIGURE_MARKS: dict[str, str | None] = {
    "fig19": "minute",
    "fig21": None,
    "fig22": "goal_index",
    "fig24": "minute",
    "fig27": "minute",
    "ablation": "learning",
    "online": "start_minutes",
    "exploration": "explore",
}
_MARKS = tuple(dict.fromkeys(mark for mark in FIGURE_MARKS.values() if mark))


def check_needs(name: str, rows: dict[int, Row], source: str) -> None:
    """BadInput unless the rows (by line number) hold the runs figure NAME draws, with the keys
    it reads and something to plot, and no TVL run of another experiment."""
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
    own = FIGURE_MARKS[name]
    for number, row in rows.items():
        marks = [mark for mark in _MARKS if mark in row]
        if row["kind"] == "tvl" and marks != ([own] if own else []):
            mark = next((m for m in marks if m != own), None)
            owners = ", ".join(figure for figure, m in FIGURE_MARKS.items() if m == mark)
            has = f"with {mark!r}" if mark else f"without {own!r}"
            raise BadInput(f"{source}:{number}: a TVL run {has} is from {owners}, not {name}")


def _alternatives(value: Any) -> str:
    return "/".join(map(str, value)) if isinstance(value, tuple) else str(value)


def select(rows: Iterable[Row], **where: Any) -> list[Row]:
    """The rows whose keys have the given values (a tuple: any of its values)."""
    return [row for row in rows if all(_is(row.get(key), value) for key, value in where.items())]


def _is(value: Any, wanted: Any) -> bool:
    return value in wanted if isinstance(wanted, tuple) else value == wanted


def distinct(rows: Iterable[Row], key: str, order: Sequence[Any] = ()) -> list[Any]:
    """The values of `key` in `order` first, then the others sorted."""
    present = {row[key] for row in rows if row.get(key) is not None}
    return [v for v in order if v in present] + sorted(present - set(order))


def mean(values: Iterable[float | None]) -> float | None:
    """The mean of the values that are not None; None if there are none."""
    known = [v for v in values if v is not None]
    return sum(known) / len(known) if known else None


def curve(rows: Iterable[Row], x: str, y: str) -> tuple[np.ndarray, np.ndarray]:
    """Mean of `y` over the rows at each value of `x` (trials averaged): (K,), (K,) arrays."""
    by_x: dict[float, list[float | None]] = {}
    for row in rows:
        by_x.setdefault(row[x], []).append(row.get(y))
    xs = sorted(v for v in by_x if mean(by_x[v]) is not None)
    return np.array(xs, dtype=float), np.array([mean(by_x[v]) for v in xs], dtype=float)


def by_trial(rows: Iterable[Row]) -> dict[int, list[Row]]:
    trials: dict[int, list[Row]] = {}
    for row in rows:
        trials.setdefault(row["seed"], []).append(row)
    return trials


def competence_times(snapshots: Iterable[Row]) -> list[float | None]:
    """Time to competence of each trial (seed) of a set of snapshot avoid runs."""
    return [time_to_competence(rows) for _, rows in sorted(by_trial(snapshots).items())]


def final_runs(snapshots: Iterable[Row]) -> list[Row]:
    """Each trial's run with its last snapshot FAM."""
    return [max(rows, key=lambda r: r["minute"]) for rows in by_trial(snapshots).values()]


def describe_competence(times: Sequence[float | None], horizon_min: float | None) -> str:
    """'7.3 (3/3)': the mean over the trials that became competent, and how many did."""
    reached = [t for t in times if t is not None]
    if not times:
        return "–"
    if not reached:
        within = f" {horizon_min:g}" if horizon_min is not None else ""
        return f"not within{within} min (0/{len(times)})"
    return f"{sum(reached) / len(reached):.1f} ({len(reached)}/{len(times)})"


def number(value: float | None, digits: int = 2) -> str:
    return "–" if value is None or not math.isfinite(value) else f"{value:.{digits}f}"


def markdown(title: str, header: Sequence[str], body: Iterable[Sequence[str]]) -> str:
    lines = [f"### {title}", "", "| " + " | ".join(header) + " |"]
    lines.append("|" + "|".join(" --- " for _ in header) + "|")
    lines += ["| " + " | ".join(cells) + " |" for cells in body]
    return "\n".join(lines) + "\n"


def learning_minutes(rows: Iterable[Row]) -> list[Row]:
    """The per-minute rows (minute, delta_v, collisions, ...) of every learn record, with its
    seed, world and config; `minute` becomes the end of that minute (1 for the first)."""
    return [
        {**minute, "minute": minute["minute"] + 1, "seed": row["seed"], "world": row["world"]}
        for row in rows
        if row["kind"] == "learn"
        for minute in row.get("minutes", [])
    ]


def method_rows(rows: list[Row], world: str, configs: Sequence[str]) -> list[list[str]]:
    """Table rows for TVL's configurations, DWA and Q-learning in one world: time to
    competence, collision rate, speed and clearance of an avoid run, collisions in learning."""
    table: list[list[str]] = []
    learnt = learning_minutes(select(rows, world=world))
    learn_rate = mean(m["collisions"] for m in learnt)
    horizon = max((m["minute"] for m in learnt), default=None)
    for config in configs:
        snapshots = select(rows, kind="tvl", world=world, config=config, behaviour="avoid")
        if not snapshots:
            continue
        last = final_runs(snapshots)
        table.append(
            [
                world,
                f"TVL {config} FAM",
                describe_competence(competence_times(snapshots), horizon),
                number(mean(r["contacts_per_min"] for r in last)),
                number(mean(r["mean_speed_mps"] for r in last)),
                number(mean(r["mean_clearance_m"] for r in last)),
                number(learn_rate),
            ]
        )
    dwa = select(rows, kind="dwa", world=world, behaviour="avoid")
    if dwa:
        table.append(
            [
                world,
                "DWA (knows the map)",
                "no learning",
                number(mean(r["contacts_per_min"] for r in dwa)),
                number(mean(r["mean_speed_mps"] for r in dwa)),
                number(mean(r["mean_clearance_m"] for r in dwa)),
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
                number(mean(r["contacts_per_min"] for r in qlearn)),
                number(mean(r["mean_speed_mps"] for r in qlearn)),
                number(mean(r["mean_clearance_m"] for r in qlearn)),
                number(mean(r["learn_collisions"] / r["learn_minutes"] for r in qlearn)),
            ]
        )
    return table


METHOD_HEADER = (
    "world",
    "method",
    "time to competence, min (trials)",
    "avoid contacts/min",
    "avoid speed m/s",
    "avoid clearance m",
    "collisions/min learning",
)
COMPETENCE_NOTE = (
    f"Time to competence: the first learning minute after which an avoid run of "
    f"{competence.COMPETENCE_RUN_MINUTES:g} simulated minutes has at most "
    f"{competence.MAX_CONTACTS_PER_MIN:g} contacts (collisions and near misses) a minute "
    f"and a mean speed of at least "
    f"{competence.MIN_MEAN_SPEED_MPS:g} m/s.\n"
)
METHOD_NOTE = (
    "Avoid columns: the FAM at the end of learning (Q-learning: its greedy policy); "
    "means over trials.\n"
)


def competence_note(rows: Iterable[Row]) -> str:
    """The definition, and a warning when the avoid runs were not of the definition's length."""
    lengths = {r["run_minutes"] for r in rows if r.get("behaviour") == "avoid"}
    other = sorted(m for m in lengths if m != competence.COMPETENCE_RUN_MINUTES)
    if not other:
        return COMPETENCE_NOTE
    minutes = ", ".join(f"{m:g}" for m in other)
    return COMPETENCE_NOTE + f"These avoid runs lasted {minutes} min: not a competence result.\n"


def qlearn_checks(qlearn: Iterable[Row]) -> list[Row]:
    """Q-learning's competence checks (greedy avoid runs during learning), with their seed and
    `minute` the learning minutes before the check."""
    return [
        {**check, "minute": check["learn_minutes"], "seed": row["seed"]}
        for row in qlearn
        for check in row.get("competence_checks", [])
    ]


def threshold_points(rows: list[Row], world: str) -> list[tuple[float, Row]]:
    """Per threshold, the means over trials and wall sides of one world's wall runs."""
    walls = select(rows, kind="tvl", world=world, behaviour=WALL_BEHAVIOURS)
    points = []
    for threshold in distinct(walls, "threshold"):
        runs = select(walls, threshold=threshold)
        points.append(
            (
                threshold,
                {
                    key: mean(r[key] for r in runs)
                    for key in ("mean_wall_clearance_m", "mean_speed_mps", "contacts_per_min")
                },
            )
        )
    return points


def prone(point: Row) -> bool:
    rate = point["contacts_per_min"]
    return rate is not None and rate > COLLISION_PRONE_PER_MIN


def goal_methods(rows: list[Row]) -> list[tuple[str, list[Row]]]:
    """(label, goal runs) for each TVL configuration and DWA."""
    goal_runs = select(rows, behaviour="goal")
    methods = [
        (f"TVL {config}", select(goal_runs, kind="tvl", config=config))
        for config in distinct(select(goal_runs, kind="tvl"), "config", ("single", "multi"))
    ]
    dwa = select(goal_runs, kind="dwa")
    return methods + ([("DWA", dwa)] if dwa else [])


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
                runs = select(runs_of, world=world, config=config, reflexes=setting)
                if not runs:
                    continue
                competent = sum(is_competent(r) for r in runs)
                table.append(
                    [
                        world,
                        config,
                        setting,
                        number(mean(r["contacts_per_min"] for r in runs)),
                        f"{number(per_min(runs, 'collisions'))} + "
                        f"{number(per_min(runs, 'near_misses'))}",
                        number(mean(r["mean_speed_mps"] for r in runs)),
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


def learning_time_rows(
    snapshots: list[Row], series: Sequence[tuple[str, str]], dwa: list[Row]
) -> tuple[list[str], list[list[str]]]:
    """Figure 27's table: per learning minute, each (config, behaviour)'s mean speed and
    contacts a minute over the trials, then the DWA's avoid run as the last row."""

    def cell(runs: list[Row]) -> str:
        return (
            f"{number(mean(r['mean_speed_mps'] for r in runs))}, "
            f"{number(mean(r['contacts_per_min'] for r in runs))}"
        )

    header = ["minute"] + [f"{c} {b}: m/s, contacts/min" for c, b in series]
    body = [
        [f"{minute:g}"]
        + [
            cell(select(snapshots, config=config, behaviour=behaviour, minute=minute))
            for config, behaviour in series
        ]
        for minute in distinct(snapshots, "minute")
    ]
    if dwa:
        body.append(["DWA (avoid)"] + [cell(dwa) if b == "avoid" else "–" for _, b in series])
    return header, body


def minute_rates(run: Row) -> list[float]:
    """A run's contacts a minute in each of its simulated minutes (`tvl run --json`'s
    `minutes`; a last, partial minute counted at its own length)."""
    return [m["contacts"] * 60.0 / m["sim_s"] for m in run["minutes"] if m["sim_s"]]


def online_conditions(rows: Iterable[Row]) -> list[tuple[float, float]]:
    """(exploration minutes before behaving, threshold) of the online experiment's runs."""
    runs = select(rows, kind="tvl", online=ONLINE_SETTINGS)
    return [
        (start, threshold)
        for start in distinct(runs, "start_minutes")
        for threshold in distinct(select(runs, start_minutes=start), "threshold")
    ]


def online_rows(rows: list[Row]) -> list[list[str]]:
    """Per start, threshold and setting: contacts a minute in the runs' first and last
    minutes and over the whole run, speed, and the episodes learnt while behaving."""
    table = []
    for start, threshold in online_conditions(rows):
        for setting in ONLINE_SETTINGS:
            runs = select(
                rows, kind="tvl", online=setting, start_minutes=start, threshold=threshold
            )
            if not runs:
                continue
            rates = [minute_rates(r) for r in runs]
            learnt = [r["learnt"]["episodes"] for r in runs if "learnt" in r]
            table.append(
                [
                    f"{start:g}",
                    f"{threshold:g}",
                    setting,
                    number(mean(r[0] for r in rates if r)),
                    number(mean(r[-1] for r in rates if r)),
                    number(mean(r["contacts_per_min"] for r in runs)),
                    number(mean(r["mean_speed_mps"] for r in runs)),
                    f"{mean(learnt):.0f}" if learnt else "–",
                    str(len(runs)),
                ]
            )
    return table


ONLINE_HEADER = (
    "explored, min",
    "threshold",
    "FAM",
    "first minute contacts/min",
    "last minute contacts/min",
    "whole run contacts/min",
    "speed m/s",
    "episodes learnt",
    "runs",
)
