"""Where two FAMs of one configuration disagree: by trajectory, and rule by rule in words."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from tvl_cli.analysis.robotdiff import RobotDifference
from tvl_cli.analysis.rules import conditions_list, rule_conditions
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam

DEFAULT_TOLERANCE_MPS = 0.01  # velocities closer than this agree: a hundredth of top speed


@dataclass(frozen=True, slots=True)
class RuleDifference:
    trajectory: str
    conditions: tuple[tuple[str, str], ...]  # (input name, fuzzy-set name), in input order
    velocities_mps: tuple[float, float]  # in the first FAM, in the second
    experience: tuple[float, float]

    @property
    def change_mps(self) -> float:
        return self.velocities_mps[1] - self.velocities_mps[0]

    def to_dict(self) -> dict[str, object]:
        return {
            "trajectory": self.trajectory,
            "conditions": conditions_list(self.conditions),
            "velocities_mps": list(self.velocities_mps),
            "experience": list(self.experience),
            "change_mps": self.change_mps,
        }

    def sentence(self) -> str:
        conditions = " AND ".join(f"{name} is {label}" for name, label in self.conditions)
        (v_a, v_b), (e_a, e_b) = self.velocities_mps, self.experience
        return (
            f"IF {conditions} THEN {self.trajectory}: {v_a:.2f} -> {v_b:.2f} m/s "
            f"(experience {e_a:.1f} -> {e_b:.1f})"
        )


@dataclass(frozen=True, slots=True)
class TrajectoryDifference:
    trajectory: str
    rules: int  # rules of this trajectory
    differing: int  # of them, those whose velocities differ by more than the tolerance
    mean_abs_change_mps: float  # over the rules either FAM has experience of; 0 if none

    def to_dict(self) -> dict[str, object]:
        return {
            "trajectory": self.trajectory,
            "rules": self.rules,
            "differing": self.differing,
            "mean_abs_change_mps": self.mean_abs_change_mps,
        }


@dataclass(frozen=True, slots=True)
class FamDifference:
    config: str
    tolerance_mps: float
    trajectories: list[TrajectoryDifference]
    largest: list[RuleDifference]  # the rules that differ most, largest first
    # How the robots the two were learnt on differ (none: one robot), which alone makes
    # their velocities differ.
    robots: list[RobotDifference] = field(default_factory=list)

    def robots_sentence(self) -> str | None:
        """What a reader must know first, when the FAMs were learnt on different robots."""
        if not self.robots:
            return None
        changed = "; ".join(r.text() for r in self.robots)
        return f"learnt on different robots ({changed}): their velocities differ for that too"

    @property
    def differing(self) -> int:
        return sum(t.differing for t in self.trajectories)

    def to_dict(self) -> dict[str, object]:
        return {
            "config": self.config,
            "tolerance_mps": self.tolerance_mps,
            "rules": sum(t.rules for t in self.trajectories),
            "differing": self.differing,
            "trajectories": [t.to_dict() for t in self.trajectories],
            "rules_differing_most": [r.to_dict() for r in self.largest],
            "robots_differ_in": [r.to_dict() for r in self.robots],
        }


def diff_fams(
    first: Fam, second: Fam, tolerance_mps: float = DEFAULT_TOLERANCE_MPS, top: int = 20
) -> FamDifference:
    """Compare two FAMs rule by rule; `top` rules that differ most are named (0: all)."""
    if not (math.isfinite(tolerance_mps) and tolerance_mps >= 0):
        raise BadInput(f"--tolerance {tolerance_mps:g} must be a speed >= 0 m/s")
    if first.config != second.config or first.trajectory_names != second.trajectory_names:
        raise BadInput(
            f"the FAMs have different configurations ({first.config.name!r} and "
            f"{second.config.name!r}): only FAMs of one configuration compare rule by rule"
        )
    trajectories: list[TrajectoryDifference] = []
    candidates: list[tuple[float, int, int, int]] = []  # (-|change|, table, row, column)
    for t, table in enumerate(first.config.tables):
        v_a, v_b = first.velocity_table(t), second.velocity_table(t)
        known = (first.experience_table(t) > 0) | (second.experience_table(t) > 0)
        change = np.abs(v_b - v_a)
        differs = change > tolerance_mps
        for column, name in enumerate(table.trajectories):
            seen = change[known[:, column], column]
            trajectories.append(
                TrajectoryDifference(
                    name,
                    rules=len(change),
                    differing=int(differs[:, column].sum()),
                    mean_abs_change_mps=float(seen.mean()) if len(seen) else 0.0,
                )
            )
        rows, columns = np.nonzero(differs)
        candidates += [
            (-change[r, c], t, int(r), int(c)) for r, c in zip(rows, columns, strict=True)
        ]
    candidates.sort()
    largest = [
        _rule(first, second, t, row, column)
        for _, t, row, column in (candidates[:top] if top > 0 else candidates)
    ]
    order = {name: i for i, name in enumerate(first.trajectory_names)}
    trajectories.sort(key=lambda d: order[d.trajectory])
    return FamDifference(first.config.name, tolerance_mps, trajectories, largest)


def _rule(first: Fam, second: Fam, t: int, row: int, column: int) -> RuleDifference:
    table = first.config.tables[t]
    return RuleDifference(
        table.trajectories[column],
        rule_conditions(table, row),
        (float(first.velocity_table(t)[row, column]), float(second.velocity_table(t)[row, column])),
        (
            float(first.experience_table(t)[row, column]),
            float(second.experience_table(t)[row, column]),
        ),
    )
