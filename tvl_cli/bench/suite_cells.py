"""The bench's cells: each one piece of work in one world with one trial's seed, whose rows
come back together and are kept together (a killed bench loses only the cells under way).

A cell batches what shares its world and its seed: a learnt cell learns one log, trains the
FAMs its runs need from it, and drives all its runs together in one RobotBatch. The other
kinds run a controller that learns nothing here (a FAM file, a Gymnasium policy), or a
reference (a DWA, Q-learning). Every cell is a frozen value, sent as it is to a local process
or a Dask worker, and known by a digest of that value: a cell whose rows are in the journal
is not run again.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from typing import Any

from tvl_cli.core.fam_config import FamConfig
from tvl_cli.core.memory import MemoryConfig
from tvl_cli.core.method import Method

# A row's columns the suite reads to know what the row is of (its entry, its claim ...).
Tags = tuple[tuple[str, Any], ...]


@dataclass(frozen=True, slots=True)
class FamPlan:
    """A FAM a learnt cell trains from its log: a configuration, from the whole log or the
    log as it stood after a number of minutes (`tvl train --until-minute`)."""

    config: FamConfig
    until_minute: float | None = None
    # Trained on the oracle labels (every point's trajectories from the true map), the
    # reference `oracle-labels`; else by the method's labels.
    true_labels: bool = False
    # Logs learnt elsewhere that the cell's log is pooled with, each as (absolute path,
    # SHA-256): the rows `pooled`, experience from other worlds and this one's together.
    pooled: tuple[tuple[str, str], ...] = ()


@dataclass(frozen=True, slots=True)
class RunPlan:
    """One behaviour run of a cell, and the columns its row is tagged with."""

    behaviour: str
    goal: tuple[float, float] | None  # metres; goal runs only
    threshold: float | None = None  # FAM-driven runs only
    fam: FamPlan | None = None  # a learnt cell's: which of its FAMs drives the run
    tags: Tags = ()


@dataclass(frozen=True, slots=True)
class LearntCell:
    """Learn a log by a method (`tvl learn`), train each FAM the runs need (`tvl train`),
    then drive every run together (`tvl run`, each as it would run alone)."""

    world: str
    seed: int
    method: Method
    method_name: str  # as the user named it: a preset, or a method file
    learn_config: str  # the FAM configuration the learner explores with
    learn_minutes: float
    run_minutes: float
    runs: tuple[RunPlan, ...]


@dataclass(frozen=True, slots=True)
class FamFileCell:
    """A FAM file as it is (learnt elsewhere), run in this world: `tvl run FAM WORLD`."""

    world: str
    seed: int
    # The file, (absolute path, SHA-256) when the bench was planned, as a PolicyCell's.
    source: tuple[str, str]
    run_minutes: float
    runs: tuple[RunPlan, ...]


@dataclass(frozen=True, slots=True)
class PolicyCell:
    """A Gymnasium policy (`module:callable`) or a saved Stable-Baselines3 model, acting on
    what `tvl/SonarRing-v0` observes, driven by the loop `tvl run` drives."""

    world: str
    seed: int
    spec: str  # as given: MODULE:CALLABLE, or ALGORITHM:FILE.zip with the file absolute
    # The model's or policy's file, (absolute path, SHA-256) when the bench was planned; None:
    # a module's policy.
    source: tuple[str, str] | None
    observe: Method  # what the environment observes through (its `method` argument)
    run_minutes: float
    runs: tuple[RunPlan, ...]


@dataclass(frozen=True, slots=True)
class DwaCell:
    """The DWA (`tvl baseline dwa`), by the map or by the sonar ring through a memory."""

    world: str
    seed: int
    sensor: str  # baselines.dwa MAP or RING
    memory: MemoryConfig
    run_minutes: float
    runs: tuple[RunPlan, ...]


@dataclass(frozen=True, slots=True)
class OracleCell:
    """The decision rule fed the true velocities (agent.true_velocities) in place of a FAM's,
    inside the method's reflexes: the oracle velocities, a reference that reads the map."""

    world: str
    seed: int
    method: Method
    run_minutes: float
    runs: tuple[RunPlan, ...]


@dataclass(frozen=True, slots=True)
class QlearnCell:
    """Tabular Q-learning (`tvl baseline qlearn`): learn in the world, then a greedy run."""

    world: str
    seed: int
    learn_minutes: float
    run_minutes: float
    runs: tuple[RunPlan, ...]  # its avoid run


Cell = LearntCell | FamFileCell | PolicyCell | DwaCell | OracleCell | QlearnCell


def cell_id(cell: Cell) -> str:
    """The cell's digest: the same cell, whatever ran it, has the same; any change of what it
    does (a setting, a run, a tag) another."""
    return hashlib.sha256(repr(cell).encode("utf-8")).hexdigest()[:16]
