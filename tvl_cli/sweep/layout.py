"""Where a sweep keeps its files, and what each cell asks its workers to do: learn a log,
train a FAM from it, then the cell's own work (sweep.work does it)."""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tvl_cli.commands.learn import LearnRequest
from tvl_cli.commands.run import OnlineLearning, RunRequest
from tvl_cli.core.fam_config import SINGLE, FamConfig
from tvl_cli.core.method import LEARNING_FIELDS, Method, MethodChoice, method_record
from tvl_cli.sweep.cell import LEARN, TVL, Cell
from tvl_cli.sweep.grid import Grid

# Where runs keep their traces (`trace = true`), named for their cells.
TRACES = "traces"


@dataclass(frozen=True, slots=True)
class Layout:
    """Where a sweep keeps its files. Absolute: a cluster's workers run elsewhere."""

    root: Path
    grid: Grid
    grid_file: Path  # named in what the grid asked for that could not be done

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

    def work_digest(self, cell: Cell) -> str | None:
        """A digest of what a learning cell's work is done by: every field of its method and
        its FAM configuration's values (None for a baseline). Its row keeps it, so that a
        sweep run again after ours changed, or a method or configuration file was edited,
        runs those cells again rather than reading back rows of what they were."""
        if cell.kind not in (LEARN, TVL):
            return None
        config = self.grid.configs[cell.config] if cell.config is not None else None
        return _digest({"method": method_record(self.method(cell)), "config": repr(config)}, 16)

    def learn_request(self, cell: Cell) -> LogRequest:
        assert cell.learn_config is not None  # every cell that learns has one
        learn = LearnRequest(
            self.world(cell),
            self.log(cell),
            cell.seed,
            cell.learn_config,
            cell.learn_params(),
            self.method(cell),
        )
        minutes = learn.learn.minutes
        return LogRequest(learn, f"{self.grid_file}: learn_minutes {minutes:g}")

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
                given(cell.behaviour),
                given(cell.threshold),
                given(cell.run_minutes),
                cell.seed,
                cell.goal_xy(),
                trace=self.trace(cell) if cell.trace else None,
                method=cell.run_method(self.method(cell)),
                learn=OnlineLearning() if cell.online else None,
            )
            return CellWork(TVL, run=run, root=self.root)
        return CellWork(cell.kind, baseline=(self.world(cell), cell, cell.baseline_method()))


def given(value: Any) -> Any:
    """A value every cell of the kind has (None only for kinds that do not read it)."""
    assert value is not None
    return value


@dataclass(frozen=True, slots=True)
class LogRequest:
    """A log to learn for the cells that share it, and the grid key its length came from."""

    learn: LearnRequest
    minutes_key: str  # the grid file and its learn_minutes, named if nothing is learnt


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
    """What a log's name adds for the method it is learnt by: the preset it is (or "method"),
    and a digest of its learning choices, so that no two methods share a log or a FAM. Ours
    is named by its choices too, not as the default: a directory's log and FAMs learnt by
    ours before ours changed are not taken for ours now."""
    record = method_record(method, LEARNING_FIELDS)
    return f"-{record['preset'] or 'method'}-{_digest(record, 8)}"


def _digest(record: dict[str, Any], length: int) -> str:
    """The first `length` hex digits of the SHA-256 of a JSON record, its keys in order."""
    return hashlib.sha256(json.dumps(record, sort_keys=True).encode()).hexdigest()[:length]
