"""FAM inference agrees with simpful's zero-order Sugeno system on random small FAMs.

Each rule becomes a simpful rule `IF (i0 IS s1) AND (i1 IS s0) THEN (out IS rule_value)` with
a crisp consequent; simpful uses min for AND and the firing-strength weighted average of
the crisp values, which is eq. 3 computed by an independent implementation.
"""

from __future__ import annotations

import numpy as np
import pytest
from simpful import FuzzySet, FuzzySystem, LinguisticVariable

from tvl_cli.core.fam import Fam, rule_set_indices
from tvl_cli.core.fam_config import FamConfig, FamInput, FamTable, Partition
from tvl_cli.core.robot_config import SONAR_COUNT

NAMES = ("TL", "T0", "TR", "TX")


def random_partition(rng: np.random.Generator) -> Partition:
    sets = int(rng.integers(2, 5))
    centres = np.cumsum(rng.uniform(0.1, 1.0, sets))
    return Partition(tuple(f"s{k}" for k in range(sets)), tuple(float(c) for c in centres))


def random_config(rng: np.random.Generator) -> FamConfig:
    """1 to 3 tables of 1 to 3 inputs (groups of 1 to 3 sonars) sharing the trajectories."""
    order = rng.permutation(NAMES)
    cuts = sorted(rng.choice(np.arange(1, len(NAMES)), int(rng.integers(0, 3)), replace=False))
    tables = []
    for t, trajectories in enumerate(np.split(order, cuts)):
        inputs = tuple(
            FamInput(
                f"in{k}",
                tuple(int(s) for s in rng.choice(SONAR_COUNT, int(rng.integers(1, 4)), False)),
                random_partition(rng),
            )
            for k in range(int(rng.integers(1, 4)))
        )
        tables.append(FamTable(f"table{t}", inputs, tuple(str(n) for n in trajectories)))
    return FamConfig("random", tuple(tables))


def simpful_system(fam: Fam, t: int) -> FuzzySystem:
    """Table t of the FAM as a Sugeno system with outputs v_<traj> and e_<traj>."""
    table = fam.config.tables[t]
    system = FuzzySystem(show_banner=False, verbose=False)
    for k, fam_input in enumerate(table.inputs):
        c = fam_input.partition.centres_m
        sets = []
        for s, name in enumerate(fam_input.partition.names):
            points = [[c[i], 1.0 if i == s else 0.0] for i in (s - 1, s, s + 1) if 0 <= i < len(c)]
            sets.append(FuzzySet(points=points, term=name))
        system.add_linguistic_variable(f"i{k}", LinguisticVariable(sets))
    velocity, experience = fam.velocity_table(t), fam.experience_table(t)
    rules = []
    for rule, sets in enumerate(rule_set_indices(table)):
        clauses = " AND ".join(
            f"(i{k} IS {fam_input.partition.names[s]})"
            for k, (fam_input, s) in enumerate(zip(table.inputs, sets, strict=True))
        )
        for column, name in enumerate(table.trajectories):
            for kind, stored in (("v", velocity), ("e", experience)):
                term = f"r{rule}_{kind}{column}"
                system.set_crisp_output_value(term, float(stored[rule, column]))
                rules.append(f"IF {clauses} THEN ({kind}_{name} IS {term})")
    system.add_rules(rules)
    return system


def simpful_perception(fam: Fam, ring: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    velocity, experience = np.empty(len(NAMES)), np.empty(len(NAMES))
    for t, table in enumerate(fam.config.tables):
        system = simpful_system(fam, t)
        for k, fam_input in enumerate(table.inputs):
            system.set_variable(f"i{k}", float(ring[list(fam_input.sonars)].min()))
        result = system.Sugeno_inference(ignore_warnings=True)
        for name in table.trajectories:
            velocity[NAMES.index(name)] = result[f"v_{name}"]
            experience[NAMES.index(name)] = result[f"e_{name}"]
    return velocity, experience


def random_fam(rng: np.random.Generator) -> Fam:
    config = random_config(rng)
    shapes = [(t.rule_count, len(t.trajectories)) for t in config.tables]
    velocities = [rng.uniform(0.0, 0.6, shape) for shape in shapes]
    experience = [rng.uniform(0.0, 20.0, shape) * (rng.random(shape) < 0.8) for shape in shapes]
    return Fam.from_tables(config, NAMES, velocities, experience)


def random_ring(rng: np.random.Generator, fam: Fam) -> np.ndarray:
    """Readings anywhere, some exactly on a centre, some beyond the last one."""
    ring = rng.uniform(0.0, 4.0, SONAR_COUNT)
    centres = [c for t in fam.config.tables for i in t.inputs for c in i.partition.centres_m]
    on_centre = rng.random(SONAR_COUNT) < 0.3
    ring[on_centre] = rng.choice(centres, int(on_centre.sum()))
    return ring


@pytest.mark.parametrize("seed", range(25))
def test_inference_agrees_with_simpful_sugeno(seed: int) -> None:
    rng = np.random.default_rng(seed)
    fam = random_fam(rng)
    for _ in range(3):
        ring = random_ring(rng, fam)
        expected_velocity, expected_experience = simpful_perception(fam, ring)
        np.testing.assert_allclose(fam.velocities(ring), expected_velocity, rtol=0, atol=1e-9)
        np.testing.assert_allclose(fam.experience(ring), expected_experience, rtol=0, atol=1e-9)


@pytest.mark.parametrize("seed", range(5))
def test_foveal_perception_agrees_with_simpful_on_rotated_rings(seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    fam = random_fam(rng)
    ring = random_ring(rng, fam)
    velocities, _ = fam.perceive(ring)
    for k in (0, 5, 11):
        expected, _ = simpful_perception(fam, ring[(np.arange(SONAR_COUNT) + k) % SONAR_COUNT])
        np.testing.assert_allclose(velocities[k], expected, rtol=0, atol=1e-9)
