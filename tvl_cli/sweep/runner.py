"""`tvl sweep`: every cell of a grid learnt, trained and run, on local processes or a Dask
cluster, into one results table, with each setting's mean and interval over its seeds.

A learning log is learnt once for every cell that shares it, a FAM trained once likewise, and
both stay in the sweep's directory for the next sweep. Each row joins results.jsonl as its run
ends, so a killed sweep loses only the runs under way, and a cell whose row is there is not
run again. Every random choice comes from the cell's seed: wherever a cell runs, its row is
the same.
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Executor
from contextlib import AbstractContextManager
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from tvl_cli.analysis.result_rows import read_results
from tvl_cli.core.errors import BadInput
from tvl_cli.io.atomic import atomic_output, check_writable
from tvl_cli.io.json_documents import document, input_file, output_path
from tvl_cli.io.lock import WriterLock
from tvl_cli.io.made import Made
from tvl_cli.io.table import Row, append_row, write_csv, write_parquet
from tvl_cli.sweep.cell import COLUMNS, Cell
from tvl_cli.sweep.executors import (
    DEFAULT_SCHEDULER_TIMEOUT_S,
    OnDashboard,
    check_timeout,
    dask_cluster,
    local_cluster,
    local_processes,
    parse_scheduler,
)
from tvl_cli.sweep.grid import FULL, read_grid
from tvl_cli.sweep.layout import TRACES, Layout
from tvl_cli.sweep.queue import work_through
from tvl_cli.sweep.summary import PlotAxes, SweepSummary, default_plot_path, plot, summarise

RESULTS = "results.jsonl"  # every row the directory has, in the order the runs ended
TABLE_CSV = "results.csv"  # the grid's rows in the grid's order, as the tables below
TABLE_PARQUET = "results.parquet"
# A row's column after the grid values: the digest of the method and FAM configuration its
# cell's work was done by (sweep.layout.Layout.work_digest), null for a baseline.
WORK_DIGEST = "work_digest"
# Cells a grid may have unless the user confirms more. The paper's figures take tens to
# hundreds of cells; beyond ten thousand a grid is more likely a list written too long than a
# study. More than memory holds are refused even then (sweep.grid.CELL_BYTES).
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


def default_out(grid: Path) -> Path:
    return Path("results") / grid.stem


@dataclass(frozen=True, slots=True)
class SweepResult:
    request: SweepRequest
    out: Path
    cells: int
    done: int  # run by this sweep
    # of them, cells whose rows were there but made by another method or configuration
    redone: int
    skipped: int  # in the results already
    rows: list[Row]  # the grid's, in the grid's order
    files: list[Path]  # written by this sweep, relative to `out`
    summary: SweepSummary  # each setting's mean and 95 % interval over its seeds
    plot: Path | None  # the plot drawn, if one was asked for

    def document(self) -> dict[str, Any]:
        request = self.request
        inputs = {
            "grid": input_file(request.grid),
            "out": str(request.out),
            "workers": request.workers if request.scheduler is None else None,
            "scheduler": request.scheduler,
            "scheduler_timeout_s": request.scheduler_timeout_s,
            "max_cells": request.max_cells,
            "size": request.size,
            "measures": None if request.measures is None else list(request.measures),
            "plot": None if request.plot is None else asdict(request.plot),
        }
        outputs = {"files": [str(path) for path in self.files], "plot": output_path(self.plot)}
        return document(
            "sweep",
            inputs,
            outputs=outputs,
            cells=self.cells,
            done=self.done,
            redone=self.redone,
            skipped=self.skipped,
        )


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
    check_timeout(request.scheduler_timeout_s)
    if request.plot_out is not None:
        check_writable(request.plot_out)  # drawn last: refused before anything is run
    root = request.out.absolute()
    if root.exists() and not root.is_dir():
        raise BadInput(f"{root}: is a file, not a directory for the sweep")
    made = Made()
    made.folder(root)
    try:
        lock = WriterLock.acquire(root / RESULTS, SWEEP_HOLDER)
        try:
            layout = Layout(root, grid, request.grid)
            return _sweep(request, layout, made, on_progress, on_dashboard)
        finally:
            lock.release()
    except Exception:
        # A sweep refused before it kept any work (a cluster that does not answer, a first
        # log too short to train) leaves nothing behind; Ctrl-C leaves what is there.
        if not _work_kept(root):
            made.take_back()
        raise


def _work_kept(root: Path) -> bool:
    """Whether a sweep's directory holds a row, a log, a FAM or a trace."""
    folders = ("logs", "fams", TRACES)
    found = any(any((root / folder).glob("*")) for folder in folders if (root / folder).is_dir())
    return found or (root / RESULTS).exists()


def _sweep(
    request: SweepRequest,
    layout: Layout,
    made: Made,
    on_progress: Callable[[int, int], None],
    on_dashboard: OnDashboard,
) -> SweepResult:
    grid = layout.grid
    written = _prepare(layout, made)
    journal = layout.root / RESULTS
    recorded = _recorded(journal)
    digests = {cell: layout.work_digest(cell) for cell in grid.cells}
    keys = {cell: (*cell.key(), digests[cell]) for cell in grid.cells}
    rows = {cell: recorded[keys[cell]] for cell in grid.cells if keys[cell] in recorded}
    todo = [cell for cell in grid.cells if cell not in rows]
    made_otherwise = {key[:-1] for key in recorded}  # grid values with a row of any work
    redone = sum(cell.key() in made_otherwise for cell in todo)
    skipped = len(rows)
    on_progress(0, len(todo))

    def record(cell: Cell, found: Row) -> None:
        # The cell's grid values, then what its work found, as the verb's --json prints it
        # (the method as the grid names it: its record is in the sweep's logs and FAMs).
        measured = {k: v for k, v in found.items() if k not in COLUMNS}
        rows[cell] = {**asdict(cell), WORK_DIGEST: digests[cell], **measured}
        append_row(journal, rows[cell])
        on_progress(len(rows) - skipped, len(todo))

    if todo:
        with _executor(request, on_dashboard) as pool:
            written += work_through(pool, layout, todo, record)
        written.append(journal)
    table = [rows[cell] for cell in grid.cells if cell in rows]
    written += write_tables(layout.root, table)
    drawn = None
    if request.plot is not None:
        drawn = request.plot_out or default_plot_path(request.out, request.plot)
        plot(table, request.plot, drawn)
    return SweepResult(
        request=request,
        out=request.out,
        cells=len(grid.cells),
        done=len(todo),
        redone=redone,
        skipped=skipped,
        rows=table,
        files=[path.relative_to(layout.root) for path in written],
        summary=summarise(table, request.measures),
        plot=drawn,
    )


def _prepare(layout: Layout, made: Made) -> list[Path]:
    """Make the sweep's folders and put a copy of each world in it, which the runs read
    (a cluster's workers see the sweep's directory, not the grid's); the copies made."""
    for folder in ("worlds", "logs", "fams", TRACES):
        made.folder(layout.root / folder)
    return put_worlds(layout.root / "worlds", layout.grid.worlds, made)


def put_worlds(folder: Path, worlds: dict[str, str], made: Made | None = None) -> list[Path]:
    """A copy of each world's text (by its name) in `folder` as NAME.txt; the copies made,
    each also told to `made`. A world is known by its name: a copy of another world by that
    name is refused, since the logs beside it were learnt there."""
    copies = []
    for name, text in worlds.items():
        copy = folder / f"{name}.txt"
        data = text.encode("utf-8")
        if copy.exists():
            if copy.read_bytes() != data:
                raise BadInput(
                    f"{copy}: another world named {name!r} than the one asked for; its logs "
                    "were learnt there (give another --out)"
                )
            continue
        with atomic_output(copy) as temporary:
            temporary.write_bytes(data)
        if made is not None:
            made.file(copy)
        copies.append(copy)
    return copies


def _recorded(journal: Path) -> dict[tuple[object, ...], Row]:
    """The journal's rows of sweeps by their grid values and the digest of what did their
    work; rows of anything else (merged in by hand, say) are kept in it but match no cell.
    Rows written before rows kept the digest match no learning cell: what they were learnt
    and run by is not known, so those cells run again."""
    found = read_results(journal).values() if journal.exists() else []
    return {
        (*(row[column] for column in COLUMNS), row.get(WORK_DIGEST)): row
        for row in found
        if all(column in row for column in COLUMNS)
    }


def _executor(request: SweepRequest, on_dashboard: OnDashboard) -> AbstractContextManager[Executor]:
    return open_executor(
        request.scheduler, request.workers, request.scheduler_timeout_s, on_dashboard
    )


def open_executor(
    scheduler: str | None, workers: int, timeout_s: float, on_dashboard: OnDashboard
) -> AbstractContextManager[Executor]:
    """Where cells run: `workers` local processes without a scheduler; else a Dask cluster
    started here (`local[:N]`) or the scheduler at that address."""
    if scheduler is None:
        return local_processes(workers)
    cluster_workers = parse_scheduler(scheduler)
    if cluster_workers is not None:
        return local_cluster(cluster_workers, on_dashboard)
    return dask_cluster(scheduler, timeout_s, on_dashboard)


def write_tables(root: Path, rows: list[Row]) -> list[Path]:
    write_csv(root / TABLE_CSV, rows)
    written = [root / TABLE_CSV]
    if write_parquet(root / TABLE_PARQUET, rows):
        written.append(root / TABLE_PARQUET)
    return written
