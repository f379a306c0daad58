"""The rows a suite sets beside ours so they can be read: references, never a method.

Each reference names what it is, whether it reads the map (the world's true geometry, or the
truth derived from it, which no robot has), and the cells it adds in one world for one trial.
A reference that learns from ours' log would add its runs to ours' cell instead, so that the
log is learnt once.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

from tvl_cli.baselines.dwa import MAP, RING
from tvl_cli.bench.suite_cells import (
    Cell,
    DwaCell,
    FamPlan,
    LearntCell,
    OracleCell,
    QlearnCell,
    RunPlan,
)
from tvl_cli.core.fam_config import SINGLE, FamConfig
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import Method

# The roles of a suite's rows: ours, a reference, a user's controller.
OURS, REFERENCE, CONTROLLER = "method", "reference", "controller"
# The behaviours the DWA has (its avoid and its goal seeking).
DWA_BEHAVIOURS = ("avoid", "goal")


@dataclass(frozen=True, slots=True)
class Setting:
    """What one world and trial of a suite asks of every row: our method and configurations,
    the behaviours and the goal, the threshold and the minutes."""

    world: str
    goal: tuple[float, float] | None  # the world's first
    seed: int
    first_trial: bool  # the suite's first trial in this world
    method: Method
    method_name: str
    configs: tuple[FamConfig, ...]
    behaviours: tuple[str, ...]
    threshold: float
    learn_minutes: float
    run_minutes: float

    def tags(self, entry: str, role: str, reads_map: bool) -> tuple[tuple[str, object], ...]:
        return (("entry", entry), ("role", role), ("reads_map", reads_map))

    def plans(
        self, behaviours: tuple[str, ...], tags: tuple[tuple[str, object], ...]
    ) -> tuple[RunPlan, ...]:
        """A run of each behaviour the setting asks for among `behaviours`, tagged."""
        return tuple(
            RunPlan(b, self.goal if b == "goal" else None, tags=tags)
            for b in self.behaviours
            if b in behaviours and (b != "goal" or self.goal is not None)
        )

    def learnt(self, method: Method, method_name: str, entry: str, role: str) -> LearntCell:
        """A method learnt in the world with the single FAM, each configuration trained from
        the one log, every behaviour run with each."""
        runs = self.runs_of_fams(self.tags(entry, role, False), true_labels=False)
        return LearntCell(
            self.world, self.seed, method, method_name, SINGLE.name, self.learn_minutes,
            self.run_minutes, runs,
        )  # fmt: skip

    def runs_of_fams(
        self,
        tags: tuple[tuple[str, object], ...],
        true_labels: bool,
        pooled: tuple[tuple[str, str], ...] = (),
    ) -> tuple[RunPlan, ...]:
        """Every behaviour run with each configuration trained from the cell's log (pooled
        with the logs of `pooled`)."""
        return tuple(
            replace(
                plan,
                threshold=self.threshold,
                fam=FamPlan(config, true_labels=true_labels, pooled=pooled),
            )
            for config in self.configs
            for plan in self.plans(self.behaviours, tags)
        )


@dataclass(frozen=True, slots=True)
class Reference:
    name: str  # its rows' entry
    label: str  # what it is, for people
    reads_map: bool
    cells: Callable[[Setting, Reference], list[Cell]]  # in one world, for one trial
    # The runs it adds to ours' learnt cell, to be trained from ours' log (learnt once).
    runs_in_ours: Callable[[Setting, Reference], tuple[RunPlan, ...]] = lambda s, r: ()


def _ideal_sonar(setting: Setting, ref: Reference) -> list[Cell]:
    """Ours with a sensor that hears every surface: nothing to remember."""
    ideal = replace(setting.method, sonar="ideal", memory=NO_MEMORY)
    return [setting.learnt(ideal, setting.method_name, ref.name, REFERENCE)]


def _dwa(sensor: str) -> Callable[[Setting, Reference], list[Cell]]:
    def cells(setting: Setting, ref: Reference) -> list[Cell]:
        # By the map the DWA knows everything a trial's seed could change but the noise of
        # the ring that tells a near miss: it runs once a world, with the first trial's seed.
        if sensor == MAP and not setting.first_trial:
            return []
        memory = setting.method.memory if sensor == RING else NO_MEMORY
        plans = setting.plans(DWA_BEHAVIOURS, setting.tags(ref.name, REFERENCE, ref.reads_map))
        return [DwaCell(setting.world, setting.seed, sensor, memory, setting.run_minutes, plans)]

    return cells


def _none(setting: Setting, ref: Reference) -> list[Cell]:
    return []


def _oracle_labels(setting: Setting, ref: Reference) -> tuple[RunPlan, ...]:
    """Every FAM of ours trained again from ours' log, each point labelling all seven
    trajectories from the true map and pose."""
    return setting.runs_of_fams(setting.tags(ref.name, REFERENCE, ref.reads_map), true_labels=True)


def _oracle_velocities(setting: Setting, ref: Reference) -> list[Cell]:
    tags = setting.tags(ref.name, REFERENCE, ref.reads_map)
    runs = tuple(
        replace(plan, threshold=setting.threshold)
        for plan in setting.plans(setting.behaviours, tags)
    )
    return [OracleCell(setting.world, setting.seed, setting.method, setting.run_minutes, runs)]


def _qlearning(setting: Setting, ref: Reference) -> list[Cell]:
    plans = setting.plans(("avoid",), setting.tags(ref.name, REFERENCE, ref.reads_map))
    if not plans:
        return []
    return [
        QlearnCell(setting.world, setting.seed, setting.learn_minutes, setting.run_minutes, plans)
    ]


REFERENCES: dict[str, Reference] = {
    ref.name: ref
    for ref in (
        Reference(
            "oracle-velocities",
            "the decision rule fed the true velocity of every view's trajectories (the map)",
            True,
            _oracle_velocities,
        ),
        Reference(
            "oracle-labels",
            "ours' logs, every point labelling all seven trajectories from the true map",
            True,
            _none,
            _oracle_labels,
        ),
        Reference(
            "ideal-sonar",
            "ours with an ideal sonar (the nearest surface at any angle, no noise, no memory)",
            False,
            _ideal_sonar,
        ),
        Reference("dwa-map", "the DWA by the true map and pose", True, _dwa(MAP)),
        Reference(
            "dwa-ring",
            "the DWA by the sonar ring, through our echo memory, placed by odometry",
            False,
            _dwa(RING),
        ),
        Reference(
            "q-learning",
            "tabular Q-learning over the single FAM's rules, learnt in the world",
            False,
            _qlearning,
        ),
    )
}
