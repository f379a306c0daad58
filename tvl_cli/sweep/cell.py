"""A sweep's cell: one piece of work by its grid values, which are the columns of its row.

A cell is a `tvl run` after the learning and training its FAM needs (kind "tvl"), the
learning alone (kind "learn"), or a baseline as `tvl baseline` runs it (kinds "dwa" and
"qlearn"); sweep.grid makes them from a grid file.
"""

from __future__ import annotations

from dataclasses import astuple, dataclass, fields, replace
from typing import Any

from tvl_cli.commands.run import parse_goal
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.memory import MemoryChoice, MemoryConfig
from tvl_cli.core.method import Method, MethodChoice, parse_reflexes, reflexes_text

# The kinds of cell, as `tvl figure` knows them among a table's rows.
TVL, LEARN, DWA, QLEARN = "tvl", "learn", "dwa", "qlearn"
KINDS_OF_CELL = (TVL, LEARN, DWA, QLEARN)
# The keys that are fields of the method, each a cell's column of that name.
METHOD_KEYS = ("exploration", "near_m", "memory")


@dataclass(frozen=True, slots=True)
class Cell:
    """One piece of work of a sweep by its grid values, which are the columns its row adds to
    what the work found and, together, the key that finds the row again. Keys a kind does
    not read are None (False for the flags)."""

    kind: str  # one of KINDS_OF_CELL
    world: str  # the world's name
    seed: int  # of the learning and of the run
    learn_config: str | None  # the FAM configuration the learner explores with
    learn_minutes: float | None
    # The cell's own fields of the method (None: the method's): the exploration rule, where
    # collision points fall (core.method.Method.near_m), and the echo memory's kind.
    exploration: str | None
    near_m: float | None
    memory: str | None
    config: str | None  # the trained FAM configuration's name
    minute: float | None  # the FAM of the log's first minutes; None: of the whole log
    behaviour: str | None
    threshold: float | None
    goal: str | None  # "X,Y" in metres for a goal run; None for the other behaviours
    run_minutes: float | None
    online: bool  # the run learns as it goes (`tvl run --learn`)
    competence_every: float | None  # Q-learning's competence checks, learning minutes apart
    trace: bool  # the run keeps its trace in the sweep's directory
    method: str | None  # as `--method` takes it: a preset's name, or a method file beside
    # the grid; None for a baseline
    reflexes: str | None  # as `--reflex` takes them
    run_memory: str | None  # the echo memory the run reads through (`tvl run --memory`);
    # None: the one its FAM was trained through

    def key(self) -> tuple[Any, ...]:
        return astuple(self)

    def learn_params(self) -> LearnParams:
        return LearnParams(minutes=self.learn_minutes or LearnParams().minutes)

    def learning_method(self, method: Method) -> Method:
        """The grid's method with the cell's own fields of it."""
        return replace(method, **self.method_fields())

    def method_fields(self) -> dict[str, Any]:
        """The fields of the method the cell gives, as Method holds them."""
        given = {name: getattr(self, name) for name in METHOD_KEYS}
        fields = {name: value for name, value in given.items() if value is not None}
        if "memory" in fields:
            fields["memory"] = MemoryConfig(fields["memory"])
        return fields

    def run_method(self, method: Method) -> MethodChoice:
        """The run's method: the cell's, with the cell's reflexes."""
        reflexes = parse_reflexes(self.reflexes or reflexes_text(method.reflexes))
        memory = MemoryChoice(kind=self.run_memory)
        return MethodChoice(method, self.method, (("reflexes", reflexes),), memory)

    def baseline_method(self) -> MethodChoice:
        """A baseline's method: alone, with the cell's reflexes, as `tvl baseline --reflex`."""
        return MethodChoice(settings=(("reflexes", parse_reflexes(self.reflexes or "none")),))

    def goal_xy(self) -> tuple[float, float] | None:
        return None if self.goal is None else parse_goal(self.goal)


COLUMNS = tuple(f.name for f in fields(Cell))
