"""The experiments' numbers: result rows (one JSON line per run) into competence times,
means and summary tables. No drawing: render.figures draws from these.

Each line of a results file (a sweep's results.jsonl) is one cell: its grid values (`kind`:
learn, tvl, dwa or qlearn; `world`, `seed`, `config`, `minute`, `behaviour`, `threshold`,
`method`, `reflexes`, ...) and what its work found, as `tvl ... --json` prints it. Trials are
the seeds; figures show their mean and 95 % interval, tables their mean ± that interval.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.analysis.intervals import Interval, interval
from tvl_cli.core import competence, jsontext
from tvl_cli.core.errors import BadInput
from tvl_cli.core.method import DEFAULT_NAME, PAPER_NAME
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.text import decoded
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
# The online experiment's runs (their `online`): the FAM fixed, or learning while behaving
# (`tvl run --learn`), by their labels.
ONLINE_SETTINGS = {False: "fixed", True: "learns"}
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
        text = decoded(path.read_bytes(), str(path))
    except FileNotFoundError:
        raise BadInput(f"{path}: no such results file") from None
    except OSError as error:
        raise BadInput(f"{path}: cannot read ({error.strerror})") from None
    rows: dict[int, Row] = {}
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip():
            continue
        where = f"{path}:{number}"
        try:
            row = jsontext.loads(line, where)
        except json.JSONDecodeError as error:
            raise BadInput(f"{where}:{error.colno}: not JSON ({error.msg})") from None
        if not isinstance(row, dict) or not isinstance(row.get("kind"), str):
            raise BadInput(f'{where}: not a run (an object with a "kind")')
        _check_types(row, where)
        rows[number] = row
    return rows


# The keys the figures read, by what they must hold. Parameters and measures are numbers
# (finite: json reads NaN and Infinity, which would show as "–"); only the measures a run may
# not have taken, and the grid values a kind of cell does not read, can be null. `minutes` (a
# learn cell's or a run's) and `competence_checks` (Q-learning's) are lists of objects whose
# keys are checked as a run's are.
_WORDS = (
    "world",
    "config",
    "learn_config",
    "behaviour",
    "method",
    "reflexes",
    "goal",
    "exploration",
    "memory",
    "run_memory",
    "trace_file",
)
_NUMBERS = (
    "seed",
    "minute",
    "coverage",
    "threshold",
    "learn_minutes",
    "run_minutes",
    "competence_every",
    "near_m",
    "delta_v",
    "learn_collisions",
    *(f.name for f in fields(RunMetrics) if f.name != "goal_reached"),
)
_MAYBE_TAKEN = (
    "mean_wall_clearance_m",
    "time_to_goal_s",
    "time_to_competence_min",
    # grid values some kinds of cell do not read
    "minute",
    "threshold",
    "learn_minutes",
    "run_minutes",
    "competence_every",
    "near_m",
)
_MAYBE_NAMED = (
    "goal", "config", "learn_config", "behaviour", "method", "reflexes", "exploration",
    "memory", "run_memory",
)  # fmt: skip
_FLAGS = ("goal_reached", "online", "trace")
_MAYBE_FLAGGED = ("goal_reached",)  # null: the run sought no goal
_LISTS = ("minutes", "competence_checks")


def _check_types(row: Row, where: str) -> None:
    """BadInput naming the first key a figure reads that does not hold what it names."""
    for key in _WORDS:
        if key in row and not isinstance(row[key], str):
            if row[key] is None and key in _MAYBE_NAMED:
                continue
            raise BadInput(f"{where}: {key!r} is {row[key]!r}, expected text")
    for key in dict.fromkeys((*_NUMBERS, *_MAYBE_TAKEN)):
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
            if row[key] is None and key in _MAYBE_FLAGGED:
                continue
            raise BadInput(f"{where}: {key!r} is {row[key]!r}, expected true or false")
    if row.get("threshold") is not None and not is_threshold(row["threshold"]):
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


def seed_interval(rows: Iterable[Row], key: str) -> Interval | None:
    """The mean of `key` over the seeds (each seed's rows averaged first: the wall sides of a
    threshold, say) and its 95 % interval; None if no row has it."""
    by_seed: dict[Any, list[float | None]] = {}
    for row in rows:
        by_seed.setdefault(row.get("seed"), []).append(row.get(key))
    means = [mean(values) for values in by_seed.values()]
    return interval([m for m in means if m is not None])


def curve(rows: Iterable[Row], x: str, y: str) -> tuple[np.ndarray, np.ndarray]:
    """Mean of `y` over the trials at each value of `x`: (K,), (K,) arrays."""
    xs, means, _ = curve_band(rows, x, y)
    return xs, means


def curve_band(rows: Iterable[Row], x: str, y: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mean of `y` over the trials (seeds) at each value of `x`, and the half width of its
    95 % interval (NaN from one trial): (K,), (K,), (K,) arrays."""
    by_x: dict[float, list[Row]] = {}
    for row in rows:
        by_x.setdefault(row[x], []).append(row)
    points = [(v, seed_interval(by_x[v], y)) for v in sorted(by_x)]
    known = [(v, shown) for v, shown in points if shown is not None]
    return (
        np.array([v for v, _ in known], dtype=float),
        np.array([shown.mean for _, shown in known], dtype=float),
        np.array([np.nan if s.half_width is None else s.half_width for _, s in known], dtype=float),
    )


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


def spread(values: Iterable[float | None], digits: int = 2) -> str:
    """'0.31 ± 0.04': the mean of the values and the half width of its 95 % interval (the
    mean alone from one value; a dash from none)."""
    return interval_text(interval([v for v in values if v is not None]), digits)


def interval_text(shown: Interval | None, digits: int = 2) -> str:
    if shown is None:
        return "–"
    if shown.half_width is None:
        return number(shown.mean, digits)
    return f"{number(shown.mean, digits)} ± {number(shown.half_width, digits)}"


# How figures and tables name a sweep's methods: ours (the default) and the paper's.
METHOD_LABELS = {DEFAULT_NAME: "ours", PAPER_NAME: "paper's method"}


def method_label(method: str | None) -> str:
    return METHOD_LABELS.get(method or DEFAULT_NAME, str(method))


def methods_of(rows: Iterable[Row]) -> list[str]:
    """The methods TVL learnt and ran by among the rows: ours first, then the paper's, then
    any method file."""
    return distinct(select(rows, kind=("tvl", "learn")), "method", tuple(METHOD_LABELS))


def markdown(title: str, header: Sequence[str], body: Iterable[Sequence[str]]) -> str:
    lines = [f"### {title}", "", "| " + " | ".join(header) + " |"]
    lines.append("|" + "|".join(" --- " for _ in header) + "|")
    lines += ["| " + " | ".join(cells) + " |" for cells in body]
    return "\n".join(lines) + "\n"


def learning_minutes(rows: Iterable[Row]) -> list[Row]:
    """The per-minute rows (minute, delta_v, collisions, ...) of every learn record, with its
    seed and world; `minute` counted from 1, so it is also when that minute ended."""
    return [
        {**minute, "seed": row["seed"], "world": row["world"]}
        for row in rows
        if row["kind"] == "learn"
        for minute in row.get("minutes", [])
    ]


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
COMPETENCE_NOTE = (
    f"Time to competence: the first learning minute after which an avoid run of "
    f"{competence.COMPETENCE_RUN_MINUTES:g} simulated minutes has at most "
    f"{competence.MAX_CONTACTS_PER_MIN:g} contacts (collisions and near misses) a minute "
    f"and a mean speed of at least "
    f"{competence.MIN_MEAN_SPEED_MPS:g} m/s.\n"
)
METHOD_NOTE = (
    "Avoid columns: the FAM at the end of learning (Q-learning: its greedy policy); "
    "mean ± 95 % interval over trials (Student's t; the mean alone from one trial). "
    "Ours is the default method; the paper's is `--method paper`.\n"
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


def threshold_points(rows: list[Row], world: str) -> list[tuple[float, dict[str, Interval | None]]]:
    """Per threshold, the means over trials (each trial's wall sides averaged) of one world's
    wall runs, with their 95 % intervals."""
    walls = select(rows, kind="tvl", world=world, behaviour=WALL_BEHAVIOURS)
    return [
        (
            threshold,
            {
                key: seed_interval(select(walls, threshold=threshold), key)
                for key in ("mean_wall_clearance_m", "mean_speed_mps", "contacts_per_min")
            },
        )
        for threshold in distinct(walls, "threshold")
    ]


def prone(point: dict[str, Interval | None]) -> bool:
    rate = point["contacts_per_min"]
    return rate is not None and rate.mean > COLLISION_PRONE_PER_MIN


def goal_methods(rows: list[Row]) -> list[tuple[str, list[Row]]]:
    """(label, goal runs) for each TVL configuration by each method, and DWA."""
    goal_runs = select(rows, behaviour="goal")
    tvl = select(goal_runs, kind="tvl")
    methods = [
        (
            f"TVL {config}, {method_label(method)}{_reading(memory)}",
            select(tvl, config=config, method=method, run_memory=memory),
        )
        for method in methods_of(tvl)
        for config in distinct(select(tvl, method=method), "config", ("single", "multi"))
        for memory in _run_memories(select(tvl, method=method, config=config))
    ]
    dwa = select(goal_runs, kind="dwa")
    return methods + ([("DWA", dwa)] if dwa else [])


def _run_memories(runs: list[Row]) -> list[str | None]:
    """The echo memories the runs read through: None (their FAM's own) first."""
    own: list[str | None] = [None] if any(r.get("run_memory") is None for r in runs) else []
    return own + distinct(runs, "run_memory")


def _reading(run_memory: str | None) -> str:
    """How a label says a run read through another echo memory than its FAM learnt with."""
    return "" if run_memory is None else f", run with memory {run_memory}"


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


def minute_rates(run: Row) -> list[float]:
    """A run's contacts a minute in each of its simulated minutes (`tvl run --json`'s
    `minutes`; a last, partial minute counted at its own length)."""
    return [m["contacts"] * 60.0 / m["sim_s"] for m in run["minutes"] if m["sim_s"]]


def online_conditions(rows: Iterable[Row]) -> list[tuple[float, float]]:
    """(exploration minutes before behaving, threshold) of the online experiment's runs."""
    runs = select(rows, kind="tvl", online=tuple(ONLINE_SETTINGS))
    return [
        (start, threshold)
        for start in distinct(runs, "minute")
        for threshold in distinct(select(runs, minute=start), "threshold")
    ]


def online_rows(rows: list[Row]) -> list[list[str]]:
    """Per start, threshold and setting: contacts a minute in the runs' first and last
    minutes and over the whole run, speed, and the episodes learnt while behaving."""
    table = []
    for start, threshold in online_conditions(rows):
        for setting, label in ONLINE_SETTINGS.items():
            runs = select(rows, kind="tvl", online=setting, minute=start, threshold=threshold)
            if not runs:
                continue
            rates = [minute_rates(r) for r in runs]
            learnt = [r["learnt"]["episodes"] for r in runs if "learnt" in r]
            table.append(
                [
                    f"{start:g}",
                    f"{threshold:g}",
                    label,
                    number(mean(r[0] for r in rates if r)),
                    number(mean(r[-1] for r in rates if r)),
                    interval_text(seed_interval(runs, "contacts_per_min")),
                    interval_text(seed_interval(runs, "mean_speed_mps")),
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
