"""`tvl bench claims`: five of the paper's claims (§5), each learnt, trained and run by every
method asked for (the paper's and ours by default), over the trials, in the claim's world.

- avoid-9min: the square and the circle, avoiding after 9 minutes of learning (single FAM).
- fig21: wall following on each side at thresholds 0.65 and 0.95 after 15 minutes, single
  FAM, in the square and the circle.
- fig22: goal seeking to each goal among the obstacles after 20 minutes, single FAM (runs of
  3 minutes).
- fig24: the single and the multi FAM trained from one 15-minute log in the square, avoiding.
- fig27: the lab, the multi FAM exploring 45 minutes, avoiding with its FAM at 5, 15 and 45.

A log serves every claim that learns the same way in the same world (Figure 21's square and
Figure 24's), and each log's runs are one cell, driven together.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from tvl_cli.analysis.claims import CLAIMS, ClaimRow, judge
from tvl_cli.analysis.wall_threshold import PAPER_FIG21
from tvl_cli.bench.generalization_suite import FULL, QUICK, TINY
from tvl_cli.bench.suite_cells import Cell, FamPlan, LearntCell, RunPlan
from tvl_cli.bench.suite_runner import BenchRun, Where, run_cells
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.core.errors import BadInput, did_you_mean
from tvl_cli.core.fam_config import MULTI, SINGLE
from tvl_cli.core.method import DEFAULT_NAME, PAPER_NAME, Method
from tvl_cli.io.json_documents import document
from tvl_cli.io.methodfile import resolve_method
from tvl_cli.sim.worldgen import bundled_world_path
from tvl_cli.sim.worldmap import WorldMap, load_world
from tvl_cli.sweep.executors import OnDashboard

METHODS = (PAPER_NAME, DEFAULT_NAME)


@dataclass(frozen=True, slots=True)
class Size:
    trials: int
    learn_minutes: dict[str, float]  # by claim; a claim's FAM snapshots come from its own
    run_minutes: float
    goal_minutes: float
    fig27_minutes: tuple[float, ...]


_LEARN_MINUTES_REPORTED = {
    "avoid-9min": 9.0,
    "fig21": 15.0,
    "fig22": 20.0,
    "fig24": 15.0,
    "fig27": 45.0,
}
SIZES = {
    # The paper's five trials, and its learning times.
    FULL: Size(5, _LEARN_MINUTES_REPORTED, 5.0, 3.0, (5.0, 15.0, 45.0)),
    QUICK: Size(3, _LEARN_MINUTES_REPORTED, 5.0, 3.0, (5.0, 15.0, 45.0)),
    # Seconds of work: that every row is made, not what they show.
    TINY: Size(1, dict.fromkeys(_LEARN_MINUTES_REPORTED, 1.0), 0.2, 0.2, (0.5, 1.0)),
}


@dataclass(frozen=True, slots=True)
class ClaimsRequest:
    methods: tuple[str, ...] = METHODS  # as named: presets or method files
    claims: tuple[str, ...] = tuple(CLAIMS)
    size: str = FULL


@dataclass(frozen=True, slots=True)
class ClaimsResult:
    request: ClaimsRequest
    trials: list[int]
    where: Where
    run: BenchRun
    verdicts: list[ClaimRow]

    def document(self) -> dict[str, Any]:
        request = self.request
        inputs = {
            "methods": list(request.methods),
            "claims": list(request.claims),
            "size": request.size,
            "trials": self.trials,
            **self.where.inputs(),
        }
        return document(
            "bench claims",
            inputs,
            **self.run.record(),
            verdicts=[row.to_dict() for row in self.verdicts],
            rows=self.run.rows,
        )


def check_claims(names: tuple[str, ...]) -> tuple[str, ...]:
    for name in names:
        if name not in CLAIMS:
            raise BadInput(f"--claim {name}: no such claim ({did_you_mean(name, list(CLAIMS))})")
    return tuple(name for name in CLAIMS if name in names) if names else tuple(CLAIMS)


def _plans(claim: str, size: Size, world: WorldMap) -> list[tuple[str, RunPlan]]:
    """The claim's runs in its world, each with the learner's configuration its log needs."""
    tags = (("claim", claim),)
    single = FamPlan(SINGLE)

    def run(behaviour: str, fam: FamPlan, threshold: float = DEFAULT_THRESHOLD,
            goal: tuple[float, float] | None = None) -> RunPlan:  # fmt: skip
        return RunPlan(behaviour, goal, threshold, fam, tags)

    if claim == "avoid-9min":
        return [(SINGLE.name, run("avoid", single))]
    if claim == "fig21":
        return [
            (SINGLE.name, run(side, single, threshold))
            for threshold in sorted(PAPER_FIG21)
            for side in ("wall-left", "wall-right")
        ]
    if claim == "fig22":
        return [(SINGLE.name, run("goal", single, goal=goal)) for goal in world.goals]
    if claim == "fig24":
        return [(SINGLE.name, run("avoid", FamPlan(c))) for c in (SINGLE, MULTI)]
    return [(MULTI.name, run("avoid", FamPlan(MULTI, m))) for m in size.fig27_minutes]


WORLDS = {
    "avoid-9min": ("square", "circle"),
    "fig21": ("square", "circle"),
    "fig22": ("obstacles",),
    "fig24": ("square",),
    "fig27": ("lab",),
}


def plan(request: ClaimsRequest) -> tuple[dict[str, str], list[Cell], list[int]]:
    """The worlds' texts, and a cell for each method, log and trial."""
    size = SIZES[request.size]
    methods = {name: resolve_method(name, label="--method") for name in request.methods}
    trials = list(range(1, size.trials + 1))
    worlds: dict[str, WorldMap] = {}
    logs: dict[tuple[str, str, float, float], list[RunPlan]] = {}
    for claim in request.claims:
        for name in WORLDS[claim]:
            world = worlds.setdefault(name, load_world(bundled_world_path(name)))
            minutes = size.goal_minutes if claim == "fig22" else size.run_minutes
            for learner, run in _plans(claim, size, world):
                key = (name, learner, size.learn_minutes[claim], minutes)
                logs.setdefault(key, []).append(run)
    cells: list[Cell] = [
        _cell(methods[m], m, key, tuple(runs), trial)
        for m in request.methods
        for key, runs in logs.items()
        for trial in trials
    ]
    return {w.name: w.text for w in worlds.values()}, cells, trials


def _cell(
    method: Method,
    name: str,
    key: tuple[str, str, float, float],
    runs: tuple[RunPlan, ...],
    trial: int,
) -> Cell:
    world, learner, learn_minutes, run_minutes = key
    return LearntCell(world, trial, method, name, learner, learn_minutes, run_minutes, runs)


def run_claims(
    request: ClaimsRequest,
    where: Where,
    on_progress: Callable[[int, int], None] = lambda done, total: None,
    on_dashboard: OnDashboard = lambda link: None,
) -> ClaimsResult:
    worlds, cells, trials = plan(request)
    done = run_cells(cells, worlds, where, on_progress, on_dashboard)
    verdicts = judge(done.rows, request.claims, request.methods)
    return ClaimsResult(request, trials, where, done, verdicts)
