"""`tvl sweep`: every cell of a grid learnt, trained and run, on local processes or a Dask
cluster, into one results table, with each setting's mean and interval over its seeds.

A learning log is learnt once for every cell that shares it, a FAM trained once likewise, and
both stay in the sweep's directory for the next sweep. Each row joins results.jsonl as its run
ends, so a killed sweep loses only the runs under way, and a cell whose row is there is not
run again. Every random choice comes from the cell's seed: wherever a cell runs, its row is
the same.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, Executor, Future, wait
from contextlib import AbstractContextManager
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

from tvl_cli.analysis.results import read_results
from tvl_cli.commands.baseline import dwa_session, qlearn_session
from tvl_cli.commands.learn import LearnRequest, learn_to_log
from tvl_cli.commands.replay import LogReplay, replay
from tvl_cli.commands.run import OnlineLearning, RunRequest, run_behaviour
from tvl_cli.commands.train import train_from_logs, write_trained
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import SINGLE, FamConfig
from tvl_cli.core.method import (
    DEFAULT,
    DEFAULT_NAME,
    LEARNING_FIELDS,
    PAPER_NAME,
    Method,
    MethodChoice,
    method_record,
)
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.lock import WriterLock
from tvl_cli.io.loglayout import STATUS_FINISHED
from tvl_cli.io.table import Row, append_row, write_csv, write_parquet
from tvl_cli.sweep.executors import (
    DEFAULT_SCHEDULER_TIMEOUT_S,
    OnDashboard,
    dask_cluster,
    local_cluster,
    local_processes,
    parse_scheduler,
)
from tvl_cli.sweep.grid import COLUMNS, DWA, FULL, LEARN, QLEARN, TVL, Cell, Grid, read_grid
from tvl_cli.sweep.summary import PlotAxes, SweepSummary, default_plot_path, plot, summarise

RESULTS = "results.jsonl"  # every row the directory has, in the order the runs ended
TABLE_CSV = "results.csv"  # the grid's rows in the grid's order, as the tables below
TABLE_PARQUET = "results.parquet"
# Where runs keep their traces (`trace = true`), named for their cells.
TRACES = "traces"
# Cells a grid may have unless the user confirms more. The paper's figures take tens to
# hundreds of cells; beyond ten thousand a grid is more likely a list written too long than a
# study, and one of 10^8 cells would not even fit in memory to be refused later.
DEFAULT_MAX_CELLS = 10_000
# Who holds a sweep's directory, as its lock refuses a second sweep there.
SWEEP_HOLDER = "another tvl sweep in this directory"


@dataclass(frozen=True, slots=True)
class SweepRequest:
    grid: Path
    out: Path
    workers: int = 1  # local processes
    # `local` or `local:N` (a Dask cluster started here), or a Dask scheduler's address:
    # its workers run the cells.
    scheduler: str | None = None
    scheduler_timeout_s: float = DEFAULT_SCHEDULER_TIMEOUT_S
    max_cells: int | None = DEFAULT_MAX_CELLS  # None: as many as the grid has
    measures: tuple[str, ...] | None = None  # the table's; None: the behaviours' headline ones
    plot: PlotAxes | None = None
    plot_out: Path | None = None  # None: beside the table, named for what it plots
    size: str = FULL  # the grid file as written, or its [quick] or [tiny] table


@dataclass(frozen=True, slots=True)
class SweepResult:
    out: Path
    cells: int
    done: int  # run by this sweep
    skipped: int  # in the results already
    rows: list[Row]  # the grid's, in the grid's order
    files: list[Path]  # written by this sweep, relative to `out`
    summary: SweepSummary  # each setting's mean and 95 % interval over its seeds
    plot: Path | None  # the plot drawn, if one was asked for


def default_out(grid: Path) -> Path:
    return Path("results") / grid.stem


@dataclass(frozen=True, slots=True)
class _Layout:
    """Where a sweep keeps its files. Absolute: a cluster's workers run elsewhere."""

    root: Path
    grid: Grid

    def world(self, cell: Cell) -> Path:
        return self.root / "worlds" / f"{cell.world}.txt"

    def method(self, cell: Cell) -> Method:
        """A TVL or learn cell's method, with its exploration and collision points."""
        assert cell.method is not None  # every cell that learns has one
        return cell.learning_method(self.grid.methods[cell.method])

    def log(self, cell: Cell) -> Path:
        # repr: two lengths never share a name, as they could rounded.
        learnt = learning_tag(self.method(cell))
        config = "" if cell.learn_config == SINGLE.name else f"-{cell.learn_config}"
        name = f"{cell.world}-s{cell.seed}-m{cell.learn_minutes!r}{config}{learnt}.h5"
        return self.root / "logs" / name

    def fam(self, cell: Cell) -> Path:
        snapshot = "" if cell.minute is None else f"-at{cell.minute!r}"
        return self.root / "fams" / f"{self.log(cell).stem}-{cell.config}{snapshot}.h5"

    def trace(self, cell: Cell) -> Path:
        digest = hashlib.sha256(repr(cell.key()).encode()).hexdigest()[:12]
        return self.root / TRACES / f"{cell.world}-s{cell.seed}-{digest}.h5"

    def learn_request(self, cell: Cell) -> LearnRequest:
        assert cell.learn_config is not None  # every cell that learns has one
        return LearnRequest(
            self.world(cell),
            self.log(cell),
            cell.seed,
            cell.learn_config,
            cell.learn_params(),
            self.method(cell),
        )

    def train_request(self, cell: Cell) -> TrainRequest:
        assert cell.config is not None  # every cell that trains has one
        return TrainRequest(
            self.fam(cell),
            self.log(cell),
            self.grid.configs[cell.config],
            self.method(cell),
            cell.minute,
        )

    def work(self, cell: Cell) -> CellWork:
        """What a cell does once its log (and FAM) are there."""
        if cell.kind == LEARN:
            return CellWork(LEARN, log=self.log(cell))
        if cell.kind == TVL:
            run = RunRequest(
                self.fam(cell),
                self.world(cell),
                _given(cell.behaviour),
                _given(cell.threshold),
                _given(cell.run_minutes),
                cell.seed,
                cell.goal_xy(),
                trace=self.trace(cell) if cell.trace else None,
                method=cell.run_method(self.method(cell)),
                learn=OnlineLearning() if cell.online else None,
            )
            return CellWork(TVL, run=run, root=self.root)
        return CellWork(cell.kind, baseline=(self.world(cell), cell, cell.baseline_method()))


def _given(value: Any) -> Any:
    """A value every cell of the kind has (None only for kinds that do not read it)."""
    assert value is not None
    return value


@dataclass(frozen=True, slots=True)
class TrainRequest:
    fam: Path
    log: Path
    config: FamConfig
    method: Method
    until_minute: float | None  # the log as it stood then; None: all of it


@dataclass(frozen=True, slots=True)
class CellWork:
    """A cell's own work, sent to a worker: its row's measures come back."""

    kind: str
    log: Path | None = None  # a learn cell's
    run: RunRequest | None = None  # a TVL cell's
    root: Path | None = None  # the sweep's directory, which a trace's row names it from
    baseline: tuple[Path, Cell, MethodChoice] | None = None  # a baseline's world and cell


def learning_tag(method: Method) -> str:
    """What a log's name adds for a method that learns otherwise than ours: its preset, or
    "method", and a digest of its learning choices, so that no two methods share a log."""
    if not method.differs(DEFAULT, LEARNING_FIELDS):
        return ""
    record = method_record(method, LEARNING_FIELDS)
    digest = hashlib.sha256(json.dumps(record, sort_keys=True).encode()).hexdigest()[:8]
    return f"-{record['preset'] or 'method'}-{digest}"


def run_sweep(
    request: SweepRequest,
    on_progress: Callable[[int, int], None] = lambda done, total: None,
    on_dashboard: OnDashboard = lambda link: None,
) -> SweepResult:
    """Run the grid's cells not yet in the results, then write the grid's table (and draw its
    plot); each run's progress as (cells done, cells to do), and a cluster's dashboard link.
    The directory is locked meanwhile: a second sweep there is refused, not run beside."""
    grid = read_grid(request.grid, request.max_cells, request.size)
    if request.scheduler is not None:
        parse_scheduler(request.scheduler)  # refused before anything is written
    root = request.out.absolute()
    if root.exists() and not root.is_dir():
        raise BadInput(f"{root}: is a file, not a directory for the sweep")
    root.mkdir(parents=True, exist_ok=True)
    lock = WriterLock.acquire(root / RESULTS, SWEEP_HOLDER)
    try:
        return _sweep(request, _Layout(root, grid), on_progress, on_dashboard)
    finally:
        lock.release()


def _sweep(
    request: SweepRequest,
    layout: _Layout,
    on_progress: Callable[[int, int], None],
    on_dashboard: OnDashboard,
) -> SweepResult:
    grid = layout.grid
    written = _prepare(layout)
    journal = layout.root / RESULTS
    recorded = _recorded(journal)
    rows = {cell: recorded[cell.key()] for cell in grid.cells if cell.key() in recorded}
    todo = [cell for cell in grid.cells if cell not in rows]
    skipped = len(rows)
    on_progress(0, len(todo))

    def record(cell: Cell, found: Row) -> None:
        # The cell's grid values, then what its work found, as the verb's --json prints it
        # (the method as the grid names it: its record is in the sweep's logs and FAMs).
        rows[cell] = {**asdict(cell), **{k: v for k, v in found.items() if k not in COLUMNS}}
        append_row(journal, rows[cell])
        on_progress(len(rows) - skipped, len(todo))

    if todo:
        with _executor(request, on_dashboard) as pool:
            written += _work(pool, layout, todo, record)
        written.append(journal)
    table = [rows[cell] for cell in grid.cells if cell in rows]
    written += _write_tables(layout.root, table)
    drawn = None
    if request.plot is not None:
        drawn = request.plot_out or default_plot_path(request.out, request.plot)
        plot(table, request.plot, drawn)
    return SweepResult(
        out=request.out,
        cells=len(grid.cells),
        done=len(todo),
        skipped=skipped,
        rows=table,
        files=[path.relative_to(layout.root) for path in written],
        summary=summarise(table, request.measures),
        plot=drawn,
    )


def _prepare(layout: _Layout) -> list[Path]:
    """Make the sweep's folders and put a copy of each world in it, which the runs read
    (a cluster's workers see the sweep's directory, not the grid's); the copies made.
    A world is known by its name: a copy of another world by that name is refused, since the
    logs beside it were learnt there."""
    for folder in ("worlds", "logs", "fams", TRACES):
        (layout.root / folder).mkdir(parents=True, exist_ok=True)
    made = []
    for name, text in layout.grid.worlds.items():
        copy = layout.root / "worlds" / f"{name}.txt"
        data = text.encode("utf-8")
        if copy.exists():
            if copy.read_bytes() != data:
                raise BadInput(
                    f"{copy}: another world named {name!r} than the grid's; its logs were "
                    "learnt there (give another --out)"
                )
            continue
        with atomic_output(copy) as temporary:
            temporary.write_bytes(data)
        made.append(copy)
    return made


def _recorded(journal: Path) -> dict[tuple[object, ...], Row]:
    """The journal's rows of sweeps by their grid values, as Cell.key() gives them; rows of
    anything else (merged in by hand, say) are kept in it but match no cell."""
    found = read_results(journal).values() if journal.exists() else []
    return {
        tuple(row[column] for column in COLUMNS): row
        for row in map(_with_new_columns, found)
        if all(column in row for column in COLUMNS)
    }


# The columns sweeps' rows gained as grids learnt to write the experiments, with the values
# a TVL run of an older sweep had.
_OLDER_RUNS = {
    "learn_config": SINGLE.name,
    "exploration": None,
    "near_m": None,
    "memory": None,
    "minute": None,
    "online": False,
    "competence_every": None,
    "trace": False,
}


def _with_new_columns(row: Row) -> Row:
    """Rows of older sweeps as a grid makes them now: of TVL runs, learnt with the single FAM
    by ours unless they ran the paper's (`reflexes = "paper"`), which then kept our echo
    memory: those match no cell now."""
    if row["kind"] != TVL or row.get("reflexes") == PAPER_NAME:
        return row
    filled = {"method": DEFAULT_NAME, **_OLDER_RUNS, **row}
    # In the columns' order, as the grid's own rows are.
    return {key: filled[key] for key in (*COLUMNS, *row) if key in filled}


def _executor(request: SweepRequest, on_dashboard: OnDashboard) -> AbstractContextManager[Executor]:
    if request.scheduler is None:
        return local_processes(request.workers)
    workers = parse_scheduler(request.scheduler)
    if workers is not None:
        return local_cluster(workers, on_dashboard)
    return dask_cluster(request.scheduler, request.scheduler_timeout_s, on_dashboard)


def _work(
    pool: Executor, layout: _Layout, cells: list[Cell], record: Callable[[Cell, Row], None]
) -> list[Path]:
    """Do each cell once what it needs is on disk (a TVL run its FAM, a learn cell its log;
    a baseline nothing), train each FAM once its log is, and learn each log that is not:
    each at most once, all as soon as they can start. Each cell's row goes to `record` as
    its work ends; the logs and FAMs made are returned."""
    waiting_for_fam: dict[Path, list[Cell]] = {}
    waiting_for_log: dict[Path, list[Cell]] = {}  # a learn cell, or a cell for each FAM
    learning: dict[Future[None], Path] = {}
    training: dict[Future[None], Path] = {}
    running: dict[Future[Row], Cell] = {}

    def train(cell: Cell) -> None:
        training[pool.submit(train_fam, layout.train_request(cell))] = layout.fam(cell)

    def do(cell: Cell) -> None:
        running[pool.submit(do_cell, layout.work(cell))] = cell

    def after_log(cell: Cell) -> None:
        do(cell) if cell.kind == LEARN else train(cell)

    def when_logged(cell: Cell) -> None:
        log = layout.log(cell)
        if log.exists():
            after_log(cell)
        elif log in waiting_for_log:
            waiting_for_log[log].append(cell)
        else:
            waiting_for_log[log] = [cell]
            learning[pool.submit(learn_log, layout.learn_request(cell))] = log

    for cell in cells:
        if cell.kind in (DWA, QLEARN):
            do(cell)
        elif cell.kind == LEARN:
            when_logged(cell)
        elif (fam := layout.fam(cell)).exists():
            do(cell)
        elif fam in waiting_for_fam:
            waiting_for_fam[fam].append(cell)
        else:
            waiting_for_fam[fam] = [cell]
            when_logged(cell)

    def under_way() -> list[Future[Any]]:
        return [*learning, *training, *running]

    made: list[Path] = []
    try:
        while under_way():
            ended, _ = wait(under_way(), return_when=FIRST_COMPLETED)
            for future in ended:
                if future in running:
                    record(running.pop(future), future.result())
                elif future in training:
                    future.result()
                    made.append(fam := training.pop(future))
                    for cell in waiting_for_fam.pop(fam):
                        do(cell)
                else:
                    future.result()
                    made.append(log := learning.pop(future))
                    for cell in waiting_for_log.pop(log):
                        after_log(cell)
    finally:
        # After a failure or Ctrl-C: what has not started never will.
        for future in under_way():
            future.cancel()
    return made


def do_cell(work: CellWork) -> Row:
    """A cell's own work, and what it found as the verb's --json prints it: a learn cell's
    log as `tvl replay` sums it up, a TVL run as `tvl run`, a baseline as `tvl baseline`."""
    if work.kind == LEARN:
        assert work.log is not None
        return _learnt(work.log)
    if work.kind == TVL:
        assert work.run is not None and work.root is not None
        found = run_behaviour(work.run).to_dict()
        if work.run.trace is not None:
            found["trace_file"] = work.run.trace.relative_to(work.root).as_posix()
        return found
    assert work.baseline is not None
    world, cell, method = work.baseline
    if work.kind == DWA:
        report = dwa_session(
            world,
            _given(cell.behaviour),
            cell.goal_xy(),
            _given(cell.run_minutes),
            cell.seed,
            method=method,
        )
        return asdict(report.metrics)
    return qlearn_session(
        world,
        _given(cell.learn_minutes),
        _given(cell.run_minutes),
        cell.seed,
        cell.competence_every or None,  # 0: no checks
        method=method,
    ).to_dict()


def _learnt(log: Path) -> Row:
    """A learning log's session and its minutes, as `tvl replay --json` gives them."""
    summary = replay(log)
    assert isinstance(summary, LogReplay)  # the sweep's logs are learning logs
    (session,) = summary.sessions  # the sweep learns each log in one session
    return {
        "episodes": session.episodes,
        "collisions": session.collisions,
        "exemplars": session.exemplars,
        "sim_minutes": session.sim_minutes,
        "coverage": session.coverage,
        "minutes": summary.minutes,
    }


def learn_log(request: LearnRequest) -> None:
    """Learn a new log whole at request.log, or leave no file there."""
    with atomic_output(request.log) as temporary:
        # learn_to_log makes the log itself (or adds to one that exists): it learns under the
        # name atomic_output reserved, renamed into place only once learning has finished.
        temporary.unlink()
        result = learn_to_log(replace(request, log=temporary))
        if result.status != STATUS_FINISHED:
            raise KeyboardInterrupt  # a signal stopped the learning: it stops the sweep too


def train_fam(request: TrainRequest) -> None:
    """Train a FAM from a log (as it stood at a minute) by a method, as `tvl train LOG -o FAM
    --method [--until-minute]` does."""
    trained = train_from_logs(
        [request.log], request.config, request.method, until_minute=request.until_minute
    )
    write_trained(request.fam, trained)


def _write_tables(root: Path, rows: list[Row]) -> list[Path]:
    write_csv(root / TABLE_CSV, rows)
    written = [root / TABLE_CSV]
    if write_parquet(root / TABLE_PARQUET, rows):
        written.append(root / TABLE_PARQUET)
    return written
