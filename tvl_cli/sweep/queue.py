"""The order a sweep's work runs in on a pool (local processes or a Dask cluster): each cell
once what it needs is on disk (a TVL run its FAM, a learn cell its log; a baseline nothing),
each FAM trained once its log is, each log that is not learnt; each at most once, all as soon
as they can start."""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, Executor, Future, wait
from pathlib import Path
from typing import Any

from tvl_cli.io.table import Row
from tvl_cli.sweep.cell import DWA, LEARN, QLEARN, Cell
from tvl_cli.sweep.layout import Layout
from tvl_cli.sweep.work import do_cell, learn_log, train_fam


def work_through(
    pool: Executor, layout: Layout, cells: list[Cell], record: Callable[[Cell, Row], None]
) -> list[Path]:
    """Do the cells' work, each cell's row to `record` as its work ends; the logs and FAMs
    made."""
    queue = _Queue(pool, layout, record)
    for cell in cells:
        queue.start(cell)
    return queue.drain()


class _Queue:
    """The work submitted and the cells waiting for it, by the file each waits for."""

    def __init__(self, pool: Executor, layout: Layout, record: Callable[[Cell, Row], None]) -> None:
        self.pool, self.layout, self.record = pool, layout, record
        self.waiting_for_fam: dict[Path, list[Cell]] = {}
        self.waiting_for_log: dict[Path, list[Cell]] = {}  # a learn cell, or one a FAM
        self.learning: dict[Future[None], Path] = {}
        self.training: dict[Future[None], Path] = {}
        self.running: dict[Future[Row], Cell] = {}

    def start(self, cell: Cell) -> None:
        """Submit what a cell needs first, or its own work if nothing."""
        if cell.kind in (DWA, QLEARN):
            self._do(cell)
        elif cell.kind == LEARN:
            self._when_logged(cell)
        elif (fam := self.layout.fam(cell)).exists():
            self._do(cell)
        elif fam in self.waiting_for_fam:
            self.waiting_for_fam[fam].append(cell)
        else:
            self.waiting_for_fam[fam] = [cell]
            self._when_logged(cell)

    def drain(self) -> list[Path]:
        """Wait for the work submitted, submitting what each end lets start; the logs and
        FAMs made."""
        made: list[Path] = []
        try:
            while self._under_way():
                ended, _ = wait(self._under_way(), return_when=FIRST_COMPLETED)
                for future in ended:
                    made += self._ended(future)
        finally:
            # After a failure or Ctrl-C: what has not started never will.
            for future in self._under_way():
                future.cancel()
        return made

    def _ended(self, future: Future[Any]) -> list[Path]:
        if future in self.running:
            self.record(self.running.pop(future), future.result())
            return []
        future.result()  # a failure of the learning or the training stops the sweep
        if future in self.training:
            fam = self.training.pop(future)
            for cell in self.waiting_for_fam.pop(fam):
                self._do(cell)
            return [fam]
        log = self.learning.pop(future)
        for cell in self.waiting_for_log.pop(log):
            self._after_log(cell)
        return [log]

    def _under_way(self) -> list[Future[Any]]:
        return [*self.learning, *self.training, *self.running]

    def _do(self, cell: Cell) -> None:
        self.running[self.pool.submit(do_cell, self.layout.work(cell))] = cell

    def _train(self, cell: Cell) -> None:
        request = self.layout.train_request(cell)
        self.training[self.pool.submit(train_fam, request)] = self.layout.fam(cell)

    def _after_log(self, cell: Cell) -> None:
        self._do(cell) if cell.kind == LEARN else self._train(cell)

    def _when_logged(self, cell: Cell) -> None:
        log = self.layout.log(cell)
        if log.exists():
            self._after_log(cell)
        elif log in self.waiting_for_log:
            self.waiting_for_log[log].append(cell)
        else:
            self.waiting_for_log[log] = [cell]
            request = self.layout.learn_request(cell)
            self.learning[self.pool.submit(learn_log, request)] = log
