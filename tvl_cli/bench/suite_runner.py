"""A suite's cells run on the sweep's engine: local processes or a Dask cluster
(sweep.runner.open_executor), a journal of rows that a killed bench goes on from, and the
suite's table written whole at the end.

Each cell's rows join results.jsonl together, in one write, as the cell ends: the journal
holds a cell whole or not at all, and a cell whose rows are there is not run again. The
directory is locked meanwhile (a second bench there is refused, not run beside).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Executor, Future, wait
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tvl_cli.analysis.result_rows import read_results
from tvl_cli.bench.suite_cells import Cell, cell_id
from tvl_cli.bench.suite_work import CELL, CELL_ROWS, FAMS, LOGS, WORLDS, Row, do_cell
from tvl_cli.core.errors import BadInput
from tvl_cli.io.lock import WriterLock
from tvl_cli.io.table import append_rows
from tvl_cli.sweep.executors import DEFAULT_SCHEDULER_TIMEOUT_S, OnDashboard, parse_scheduler
from tvl_cli.sweep.runner import RESULTS, open_executor, put_worlds, write_tables

# Who holds a bench's directory, as its lock refuses a second bench there.
BENCH_HOLDER = "another tvl bench in this directory"


@dataclass(frozen=True, slots=True)
class Where:
    """Where a suite's cells run and keep their files."""

    out: Path
    workers: int = 1  # local processes
    scheduler: str | None = None  # local[:N] or a Dask scheduler's address: its workers
    scheduler_timeout_s: float = DEFAULT_SCHEDULER_TIMEOUT_S

    def inputs(self) -> dict[str, Any]:
        """Where the cells ran, as a bench's document echoes it."""
        return {
            "out": str(self.out),
            "workers": self.workers if self.scheduler is None else None,
            "scheduler": self.scheduler,
            "scheduler_timeout_s": self.scheduler_timeout_s,
        }


@dataclass(frozen=True, slots=True)
class BenchRun:
    rows: list[Row]  # every row of the suite's cells, in the cells' order
    cells: int
    done: int  # cells run by this bench
    skipped: int  # cells whose rows were in the journal already
    files: list[Path]  # written by this bench, relative to the directory
    wall_s: float  # this bench's, cells done before not counted
    cpu_s: float  # every cell's, those done before included: the work the rows cost

    def record(self) -> dict[str, Any]:
        """What the bench wrote and did, as its document records it (the rows apart)."""
        return {
            "outputs": {"files": [str(path) for path in self.files]},
            "cells": self.cells,
            "done": self.done,
            "skipped": self.skipped,
            "wall_s": self.wall_s,
            "cpu_s": self.cpu_s,
        }


def run_cells(
    cells: list[Cell],
    worlds: dict[str, str],
    where: Where,
    on_progress: Callable[[int, int], None] = lambda done, total: None,
    on_dashboard: OnDashboard = lambda link: None,
) -> BenchRun:
    """Run the cells not yet in the directory's journal (the worlds' texts copied there for
    them to read by name), then write the table of every cell's rows."""
    started = time.perf_counter()
    if where.scheduler is not None:
        parse_scheduler(where.scheduler)  # refused before anything is written
    root = where.out.absolute()
    if root.exists() and not root.is_dir():
        raise BadInput(f"{root}: is a file, not a directory for the bench")
    root.mkdir(parents=True, exist_ok=True)
    lock = WriterLock.acquire(root / RESULTS, BENCH_HOLDER)
    try:
        for folder in (WORLDS, LOGS, FAMS):
            (root / folder).mkdir(exist_ok=True)
        written = put_worlds(root / WORLDS, worlds)
        journal = root / RESULTS
        found = _recorded(journal)
        ids = [cell_id(cell) for cell in cells]
        todo = [cell for cell, named in zip(cells, ids, strict=True) if named not in found]
        on_progress(0, len(todo))
        if todo:
            with open_executor(
                where.scheduler, where.workers, where.scheduler_timeout_s, on_dashboard
            ) as pool:
                for count, rows in enumerate(_each_done(pool, todo, root), start=1):
                    append_rows(journal, rows)
                    found[rows[0][CELL]] = rows
                    on_progress(count, len(todo))
            written.append(journal)
        table = [row for named in dict.fromkeys(ids) for row in found[named]]
        written += write_tables(root, table)
    finally:
        lock.release()
    return BenchRun(
        rows=table,
        cells=len(set(ids)),
        done=len(todo),
        skipped=len(set(ids)) - len(todo),
        files=[path.relative_to(root) for path in written],
        wall_s=time.perf_counter() - started,
        cpu_s=sum(row.get("cell_cpu_s", 0.0) for row in table),
    )


def _each_done(pool: Executor, cells: list[Cell], root: Path) -> Iterator[list[Row]]:
    """Each cell's rows as it ends, the longest cells sent first; after a failure or Ctrl-C
    what has not started never will."""
    running: dict[Future[list[Row]], Cell] = {
        pool.submit(do_cell, cell, root): cell
        for cell in sorted(cells, key=_expected_work, reverse=True)
    }
    try:
        while running:
            ended, _ = wait(running, return_when=FIRST_COMPLETED)
            for future in ended:
                running.pop(future)
                yield future.result()
    finally:
        for future in running:
            future.cancel()


def _expected_work(cell: Cell) -> float:
    """About how long a cell takes, to send the longest first: its simulated minutes."""
    learning = getattr(cell, "learn_minutes", 0.0)
    return learning + cell.run_minutes * len(cell.runs)


def _recorded(journal: Path) -> dict[str, list[Row]]:
    """The journal's cells, each with its rows, if it holds them all; rows of anything else
    (merged in by hand, say) are kept in it but match no cell."""
    rows = read_results(journal).values() if journal.exists() else []
    cells: dict[str, list[Row]] = {}
    for row in rows:
        if isinstance(row.get(CELL), str):
            cells.setdefault(row[CELL], []).append(row)
    return {named: found for named, found in cells.items() if len(found) == found[0][CELL_ROWS]}
