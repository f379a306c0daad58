"""Why a ring is perceived as it is: the fuzzy sets each input fires, the rules that fire,
and the weighted averages they make (what `tvl inspect --explain` prints)."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from tvl_cli.core.fam_config import FamInput, FamTable
from tvl_cli.core.fuzzy import memberships


@dataclass(frozen=True, slots=True)
class FiredSet:
    """A fuzzy set with a non-zero membership, and that membership."""

    name: str
    degree: float


@dataclass(frozen=True, slots=True)
class InputReading:
    """One input of one table for an explained ring."""

    table: str
    name: str
    sonars: tuple[int, ...]
    value_m: float
    fired: tuple[FiredSet, ...]


@dataclass(frozen=True, slots=True)
class FiredRule:
    """A rule with non-zero strength, with what it stores for its table's trajectories."""

    table: str
    rule: int
    sets: tuple[int, ...]  # fuzzy-set index of each input
    set_names: tuple[str, ...]
    strength: float
    trajectories: tuple[str, ...]
    velocities_mps: tuple[float, ...]
    experience: tuple[float, ...]


@dataclass(frozen=True, slots=True)
class Explanation:
    """Why a ring is perceived as it is: memberships, fired rules, and the weighted averages."""

    inputs: tuple[InputReading, ...]
    rules: tuple[FiredRule, ...]
    trajectories: tuple[str, ...]
    velocities_mps: tuple[float, ...]
    experience: tuple[float, ...]

    def to_dict(self) -> dict[str, Any]:
        """Plain lists, dicts and numbers, as for JSON."""
        return asdict(self)


def reading(table: FamTable, fam_input: FamInput, value_m: float) -> InputReading:
    """An input's reading and the (at most two) fuzzy sets it fires."""
    lower, upper = memberships(fam_input.partition, np.array([value_m]))
    k, degree = int(lower[0]), float(upper[0])
    names = fam_input.partition.names[k : k + 2]
    fired = zip(names, (1.0 - degree, degree), strict=True)
    return InputReading(
        table.name,
        fam_input.name,
        fam_input.sonars,
        value_m,
        tuple(FiredSet(name, d) for name, d in fired if d > 0),
    )


def restricted(explanation: Explanation, trajectories: tuple[str, ...]) -> Explanation:
    """The explanation of only these trajectories: each fired rule keeps what it stores for
    them, and rules that store none of them are left out."""
    rules = []
    for rule in explanation.rules:
        keep = [i for i, name in enumerate(rule.trajectories) if name in trajectories]
        if keep:
            rules.append(
                FiredRule(
                    rule.table,
                    rule.rule,
                    rule.sets,
                    rule.set_names,
                    rule.strength,
                    tuple(rule.trajectories[i] for i in keep),
                    tuple(rule.velocities_mps[i] for i in keep),
                    tuple(rule.experience[i] for i in keep),
                )
            )
    keep = [i for i, name in enumerate(explanation.trajectories) if name in trajectories]
    return Explanation(
        explanation.inputs,
        tuple(rules),
        tuple(explanation.trajectories[i] for i in keep),
        tuple(explanation.velocities_mps[i] for i in keep),
        tuple(explanation.experience[i] for i in keep),
    )
