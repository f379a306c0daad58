"""`tvl bench generalization`: how competent the robot is in generated worlds nobody tuned on.

For each world (`tvl world new rooms --seed N`) and trial (the seed of learning and runs):
learn from the world's start with the single FAM, train each configuration from that one
log, and run avoid, wall-left, wall-right and goal (the world's first goal) with each. Beside
ours, the references (bench.references) and the user's controllers run in the same worlds
with the same seeds. The test worlds (rooms seeds 1001-1020) are for reporting only; the
tuning set (seeds 1-20) is for choosing.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass, replace
from typing import Any

from tvl_cli.analysis.generalization import Figures, summarise
from tvl_cli.bench.controllers import FAM, METHOD, Controller
from tvl_cli.bench.references import CONTROLLER, OURS, REFERENCES, Setting
from tvl_cli.bench.suite_cells import Cell, FamFileCell, PolicyCell
from tvl_cli.bench.suite_runner import BenchRun, Where, run_cells
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS, FamConfig
from tvl_cli.core.method import Method, method_record
from tvl_cli.io.json_documents import document
from tvl_cli.sim.worldgen import generate_world
from tvl_cli.sim.worldmap import parse_world
from tvl_cli.sweep.executors import OnDashboard

KIND = "rooms"
TEST, TUNING = "test", "tuning"
WORLD_SETS = {TEST: range(1001, 1021), TUNING: range(1, 21)}
BEHAVIOURS = ("avoid", "wall-left", "wall-right", "goal")
# What a Gymnasium controller is scored on: the environment's tasks that mean what they mean
# to `tvl run` (its `wall` task keeps a distance on either side).
CONTROLLER_BEHAVIOURS = ("avoid", "goal")
TINY, QUICK, FULL = "tiny", "quick", "full"
# The rows of ours' FAMs trained from each world's log pooled with logs learnt elsewhere.
POOLED = "pooled"


@dataclass(frozen=True, slots=True)
class Size:
    worlds: int  # the first of the set
    trials: int
    learn_minutes: float
    run_minutes: float


SIZES = {
    # Seconds of work: that every row is made, not what they show.
    TINY: Size(2, 1, 1.0, 0.5),
    # A look while developing: a quarter of the worlds, two trials.
    QUICK: Size(5, 2, 15.0, 5.0),
    FULL: Size(20, 3, 15.0, 5.0),
}


@dataclass(frozen=True, slots=True)
class Entry:
    """What a group of rows is of: ours, a reference, or a user's controller."""

    name: str
    role: str
    reads_map: bool
    label: str


@dataclass(frozen=True, slots=True)
class GeneralizationRequest:
    method: Method
    method_name: str = "default"
    world_set: str = TEST
    span: tuple[int, int] | None = None  # the set's A-th to B-th world, from 1
    trials: int | None = None  # None: the size's
    size: str = FULL
    configs: tuple[FamConfig, ...] = tuple(BUILTIN_FAM_CONFIGS.values())
    controllers: tuple[Controller, ...] = ()
    observe: Method | None = None  # what policies observe through; None: our method
    references: tuple[str, ...] = tuple(REFERENCES)
    threshold: float = DEFAULT_THRESHOLD
    # Logs learnt elsewhere, each (absolute path, SHA-256), pooled with each world's own log
    # for the rows `pooled`; none: no such rows.
    pool: tuple[tuple[str, str], ...] = ()


@dataclass(frozen=True, slots=True)
class Plan:
    world_seeds: list[int]
    trials: list[int]
    size: Size
    worlds: dict[str, str]  # name -> text
    entries: list[Entry]
    cells: list[Cell]


def world_seeds(request: GeneralizationRequest) -> list[int]:
    """The set's worlds at the request's size, or its span."""
    seeds = list(WORLD_SETS[request.world_set])
    if request.span is None:
        return seeds[: SIZES[request.size].worlds]
    first, last = request.span
    if not 1 <= first <= last <= len(seeds):
        # `--worlds 1001` counts worlds and does not name a seed: say which seeds they are.
        shown = str(last) if first == 1 else f"{first}-{last}"
        raise BadInput(
            f"--worlds {shown}: the {request.world_set} set's worlds are 1 to {len(seeds)}, "
            f"counted from 1 (rooms seeds {seeds[0]} to {seeds[-1]})"
        )
    return seeds[first - 1 : last]


def plan(request: GeneralizationRequest) -> Plan:
    """Every cell of the suite: for each world and trial, ours, each reference asked for and
    each controller."""
    size = SIZES[request.size]
    names = {request.method_name, *request.references, *([POOLED] if request.pool else [])}
    for controller in request.controllers:
        if controller.name in names:
            raise BadInput(f"--controller {controller.name}: a row of that name is there already")
        names.add(controller.name)
    seeds = world_seeds(request)
    trials = list(range(1, (request.trials or size.trials) + 1))
    worlds: dict[str, str] = {}
    cells: list[Cell] = []
    for world_seed in seeds:
        text = generate_world(KIND, None, None, world_seed)
        world = parse_world(text, f"{KIND}-s{world_seed}")
        worlds[world.name] = text
        for trial in trials:
            setting = Setting(
                world.name,
                world.goals[0] if world.goals else None,
                trial,
                trial == trials[0],
                request.method,
                request.method_name,
                request.configs,
                BEHAVIOURS,
                request.threshold,
                size.learn_minutes,
                size.run_minutes,
            )
            cells += _cells(request, setting)
    return Plan(seeds, trials, size, worlds, entries(request), cells)


def entries(request: GeneralizationRequest) -> list[Entry]:
    ours = Entry(request.method_name, OURS, False, f"ours: method {request.method_name}")
    refs = [REFERENCES[name] for name in request.references]
    pooled = [
        Entry(
            POOLED,
            OURS,
            False,
            f"ours, each world's log pooled with {len(request.pool)} learnt elsewhere",
        )
    ]
    return [
        ours,
        *(pooled if request.pool else []),
        *(Entry(r.name, "reference", r.reads_map, r.label) for r in refs),
        *(Entry(c.name, CONTROLLER, False, c.label) for c in request.controllers),
    ]


def _cells(request: GeneralizationRequest, setting: Setting) -> list[Cell]:
    name = request.method_name
    ours = setting.learnt(request.method, name, name, OURS)
    refs = [REFERENCES[ref] for ref in request.references]
    pooled = (
        setting.runs_of_fams(setting.tags(POOLED, OURS, False), False, request.pool)
        if request.pool
        else ()
    )
    added = pooled + tuple(p for r in refs for p in r.runs_in_ours(setting, r))
    cells: list[Cell] = [replace(ours, runs=ours.runs + added)]
    for ref in refs:
        cells += ref.cells(setting, ref)
    for controller in request.controllers:
        cells.append(_controller_cell(request, setting, controller))
    return cells


def _controller_cell(
    request: GeneralizationRequest, setting: Setting, controller: Controller
) -> Cell:
    tags = setting.tags(controller.name, CONTROLLER, False)
    if controller.kind == METHOD:
        assert controller.method is not None
        return setting.learnt(controller.method, controller.spec, controller.name, CONTROLLER)
    if controller.kind == FAM:
        runs = tuple(
            replace(plan, threshold=request.threshold) for plan in setting.plans(BEHAVIOURS, tags)
        )
        assert controller.source is not None
        return FamFileCell(
            setting.world, setting.seed, controller.source, setting.run_minutes, runs
        )
    observe = request.observe or request.method
    plans = setting.plans(CONTROLLER_BEHAVIOURS, tags)
    return PolicyCell(
        setting.world, setting.seed, controller.spec, controller.source, observe,
        setting.run_minutes, plans,
    )  # fmt: skip


@dataclass(frozen=True, slots=True)
class GeneralizationResult:
    request: GeneralizationRequest
    plan: Plan
    where: Where
    run: BenchRun
    figures: list[Figures]

    def document(self) -> dict[str, Any]:
        request, plan = self.request, self.plan
        inputs = {
            "set": request.world_set,
            "worlds": plan.world_seeds,
            "trials": plan.trials,
            "size": request.size,
            "learn_minutes": plan.size.learn_minutes,
            "run_minutes": plan.size.run_minutes,
            "threshold": request.threshold,
            "method_name": request.method_name,
            "method": method_record(request.method),
            "configs": [config.name for config in request.configs],
            "controllers": [
                {"name": c.name, "kind": c.kind, "spec": c.spec} for c in request.controllers
            ],
            "observe": None if request.observe is None else method_record(request.observe),
            "references": list(request.references),
            "pool": [{"path": path, "sha256": digest} for path, digest in request.pool],
            **self.where.inputs(),
        }
        return document(
            "bench generalization",
            inputs,
            **self.run.record(),
            entries=[asdict(entry) for entry in plan.entries],
            figures=[figures.to_dict() for figures in self.figures],
            rows=self.run.rows,
        )


def run_generalization(
    request: GeneralizationRequest,
    where: Where,
    on_progress: Callable[[int, int], None] = lambda done, total: None,
    on_dashboard: OnDashboard = lambda link: None,
) -> GeneralizationResult:
    """Plan the suite, run the cells not yet done, and sum the rows up."""
    planned = plan(request)
    done = run_cells(planned.cells, planned.worlds, where, on_progress, on_dashboard)
    return GeneralizationResult(request, planned, where, done, summarise(done.rows, BEHAVIOURS))
