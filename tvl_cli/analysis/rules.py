"""The rules of a FAM as a person reads them: IF front is VN AND ... THEN T1L = 0.43 m/s."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam, rule_set_indices
from tvl_cli.core.fam_config import FamTable

SORT_KEYS = ("experience", "velocity")


@dataclass(frozen=True, slots=True)
class Rule:
    trajectory: str
    conditions: tuple[tuple[str, str], ...]  # (input name, fuzzy-set name), in input order
    velocity_mps: float
    experience: float

    def to_dict(self) -> dict[str, object]:
        return {
            "trajectory": self.trajectory,
            "conditions": conditions_list(self.conditions),
            "velocity_mps": self.velocity_mps,
            "experience": self.experience,
        }

    def to_row(self) -> dict[str, object]:
        """One flat row: the trajectory, each input's fuzzy set, the velocity, the experience."""
        return {
            "trajectory": self.trajectory,
            **dict(self.conditions),
            "velocity_mps": self.velocity_mps,
            "experience": self.experience,
        }

    def sentence(self) -> str:
        conditions = " AND ".join(f"{name} is {label}" for name, label in self.conditions)
        return (
            f"IF {conditions} THEN {self.trajectory} = {self.velocity_mps:.2f} m/s  "
            f"(experience {self.experience:.1f})"
        )


def conditions_list(conditions: tuple[tuple[str, str], ...]) -> list[dict[str, str]]:
    """A rule's IF part as JSON: a record an input, in input order (an input's name, such as
    `front-left`, is a value, not a key)."""
    return [{"input": name, "set": label} for name, label in conditions]


def select_rules(
    fam: Fam,
    trajectory: str | None = None,
    top: int = 0,
    sort: str = "experience",
    untrained: bool = False,
) -> list[Rule]:
    """Rules sorted by `sort` (descending); untrained rules only with `untrained`; 0 = all."""
    if trajectory is not None and trajectory not in fam.trajectory_names:
        raise BadInput(
            f"unknown trajectory {trajectory!r} (choose from {', '.join(fam.trajectory_names)})"
        )
    if sort not in SORT_KEYS:
        raise BadInput(f"unknown sort key {sort!r} (choose from {', '.join(SORT_KEYS)})")
    # Candidates as flat arrays first, so only the rules shown become objects.
    where: list[tuple[int, int, np.ndarray]] = []  # (table, column, rows)
    for t, table in enumerate(fam.config.tables):
        experience = fam.experience_table(t)
        for column, name in enumerate(table.trajectories):
            if trajectory is None or name == trajectory:
                trained = experience[:, column] > 0
                where.append((t, column, np.flatnonzero(~trained if untrained else trained)))
    if not where:
        return []
    source = np.concatenate([np.full(len(rows), i) for i, (_, _, rows) in enumerate(where)])
    rows = np.concatenate([rows for _, _, rows in where])
    values = np.concatenate(
        [
            (fam.experience_table(t) if sort == "experience" else fam.velocity_table(t))[r, c]
            for t, c, r in where
        ]
    )
    order = np.argsort(-values, kind="stable")
    if top > 0:
        order = order[:top]
    found = []
    for i in order:
        t, column, _ = where[source[i]]
        table = fam.config.tables[t]
        row = int(rows[i])
        found.append(
            Rule(
                table.trajectories[column],
                rule_conditions(table, row),
                float(fam.velocity_table(t)[row, column]),
                float(fam.experience_table(t)[row, column]),
            )
        )
    return found


def rule_conditions(table: FamTable, row: int) -> tuple[tuple[str, str], ...]:
    """Rule `row` of a table as (input name, fuzzy-set name) pairs, in input order."""
    sets = rule_set_indices(table, np.array(row))
    return tuple((f.name, f.partition.names[s]) for f, s in zip(table.inputs, sets, strict=True))


def parse_ring(text: str, sonar_count: int) -> np.ndarray:
    """'R0,R1,...,R15' in metres -> (16,) array; BadInput if malformed."""
    parts = [p.strip() for p in text.split(",")]
    if len(parts) != sonar_count:
        raise BadInput(f"--explain needs {sonar_count} comma-separated ranges, got {len(parts)}")
    try:
        ring = np.array([float(p) for p in parts])
    except ValueError:
        raise BadInput(f"--explain: not a number in {text!r}") from None
    if not np.isfinite(ring).all() or (ring < 0).any():
        raise BadInput("--explain: ranges must be finite metres >= 0")
    return ring
