"""The FAM: training (eq. 1-2), inference (eq. 3), symmetric learning, foveal rotation."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam, rule_set_indices
from tvl_cli.core.fam_config import (
    DESIGNED,
    MULTI,
    SINGLE,
    FamConfig,
    FamInput,
    FamTable,
    Partition,
)
from tvl_cli.core.fam_config_json import fam_config_from_json, validate_fam_config
from tvl_cli.core.robot_config import ALL_TRAJECTORY_NAMES, SONAR_COUNT, mirror_sonar, sonars_within

NAMES = ALL_TRAJECTORY_NAMES  # T3L T2L T1L T0 T1R T2R T3R
T1L, T0, T1R = NAMES.index("T1L"), NAMES.index("T0"), NAMES.index("T1R")
MIRROR = np.array([mirror_sonar(i) for i in range(SONAR_COUNT)])
ring_values = st.lists(st.floats(0.15, 4.0), min_size=SONAR_COUNT, max_size=SONAR_COUNT)


def random_rings(rng: np.random.Generator, count: int) -> np.ndarray:
    return rng.uniform(0.15, 4.0, (count, SONAR_COUNT))  # (N, 16) metres


def trained(config: FamConfig, seed: int = 0, count: int = 3000) -> Fam:
    rng = np.random.default_rng(seed)
    fam = Fam(config, NAMES)
    fam.train(
        random_rings(rng, count), rng.integers(0, len(NAMES), count), rng.uniform(0, 0.6, count)
    )
    return fam


def tables(fam: Fam) -> list[tuple[np.ndarray, np.ndarray]]:
    return [(fam.velocity_table(t), fam.experience_table(t)) for t in range(len(fam.config.tables))]


def on_centres(table: FamTable, sets: tuple[int, ...]) -> np.ndarray:
    """A ring whose every input of `table` reads the centre of the given set."""
    ring = np.full(SONAR_COUNT, 4.0)
    for fam_input, s in zip(table.inputs, sets, strict=True):
        ring[list(fam_input.sonars)] = fam_input.partition.centres_m[s]
    return ring


@pytest.fixture(scope="module")
def single() -> Fam:
    return trained(SINGLE)


@pytest.fixture(scope="module")
def multi() -> Fam:
    return trained(MULTI)


@pytest.fixture(scope="module")
def fams(single: Fam, multi: Fam) -> dict[str, Fam]:
    return {"single": single, "multi": multi, "designed": trained(DESIGNED)}


def test_shipped_configurations_have_the_papers_sizes() -> None:
    assert SINGLE.rule_count == 720
    # The paper's multi FAM maps to 125,720 regions; ours is within 2 % of it.
    assert abs(MULTI.rule_count - 125_720) / 125_720 < 0.02
    assert MULTI.tables[NAMES.index("T1L")].rule_count == 31_250


def test_exemplar_on_set_centres_trains_exactly_one_rule_to_its_velocity() -> None:
    fam = Fam(SINGLE, NAMES)
    sets = (1, 3, 0, 2, 1)
    fam.train(on_centres(SINGLE.tables[0], sets)[None], np.array([T1L]), np.array([0.37]), False)
    experience, velocity = fam.experience_table(0), fam.velocity_table(0)
    rule = np.ravel_multi_index(sets, SINGLE.tables[0].shape)
    assert np.count_nonzero(experience) == 1
    assert experience[rule, T1L] == 1.0
    assert velocity[rule, T1L] == 0.37
    untouched = np.ones(velocity.shape, dtype=bool)
    untouched[rule, T1L] = False
    assert (velocity[untouched] == 0.1).all()


def test_exemplar_halfway_between_two_centres_splits_its_weight_evenly() -> None:
    fam = Fam(SINGLE, NAMES)
    table = SINGLE.tables[0]
    ring = on_centres(table, (1, 3, 0, 2, 1))
    front = table.inputs[0]
    low, high = front.partition.centres_m[1:3]
    ring[list(front.sonars)] = (low + high) / 2
    fam.train(ring[None], np.array([T0]), np.array([0.5]), symmetric=False)
    experience = fam.experience_table(0)[:, T0]
    rules = np.ravel_multi_index(([1, 2], [3, 3], [0, 0], [2, 2], [1, 1]), table.shape)
    assert np.count_nonzero(experience) == 2
    np.testing.assert_allclose(experience[rules], [0.5, 0.5], rtol=1e-12)
    np.testing.assert_allclose(fam.velocity_table(0)[rules, T0], [0.5, 0.5], rtol=1e-12)


@pytest.mark.parametrize("config", [SINGLE, MULTI], ids=lambda c: c.name)
def test_training_in_two_batches_equals_training_once_on_both(config: FamConfig) -> None:
    rng = np.random.default_rng(1)
    rings, trajectories, labels = (
        random_rings(rng, 500),
        rng.integers(0, 7, 500),
        rng.uniform(0, 0.6, 500),
    )
    once, twice = Fam(config, NAMES), Fam(config, NAMES)
    once.train(rings, trajectories, labels)
    twice.train(rings[:200], trajectories[:200], labels[:200])
    twice.train(rings[200:], trajectories[200:], labels[200:])
    for (v1, e1), (v2, e2) in zip(tables(once), tables(twice), strict=True):
        np.testing.assert_allclose(e2, e1, rtol=1e-12, atol=0)
        np.testing.assert_allclose(v2, v1, rtol=1e-12, atol=0)


@pytest.mark.parametrize("config", [SINGLE, MULTI], ids=lambda c: c.name)
def test_repeating_exemplars_doubles_experience_and_keeps_velocities(config: FamConfig) -> None:
    rng = np.random.default_rng(2)
    rings, trajectories, labels = (
        random_rings(rng, 300),
        rng.integers(0, 7, 300),
        rng.uniform(0, 0.6, 300),
    )
    fam = Fam(config, NAMES)
    fam.train(rings, trajectories, labels)
    before = tables(fam)
    fam.train(rings, trajectories, labels)
    for (v1, e1), (v2, e2) in zip(before, tables(fam), strict=True):
        np.testing.assert_array_equal(e2, 2 * e1)
        np.testing.assert_array_equal(v2, v1)


def test_training_is_deterministic() -> None:
    a, b = trained(MULTI, seed=3, count=500), trained(MULTI, seed=3, count=500)
    for (v1, e1), (v2, e2) in zip(tables(a), tables(b), strict=True):
        assert v1.tobytes() == v2.tobytes() and e1.tobytes() == e2.tobytes()


@pytest.mark.parametrize("config", [SINGLE, MULTI], ids=lambda c: c.name)
def test_untrained_inputs_are_perceived_at_the_initial_velocity(config: FamConfig) -> None:
    fam = Fam(config, NAMES)
    rings = random_rings(np.random.default_rng(4), 50)
    np.testing.assert_allclose(fam.velocities(rings), 0.1, rtol=1e-12)
    assert (fam.experience(rings) == 0).all()
    velocities, experience = fam.perceive(rings[0])
    np.testing.assert_allclose(velocities, 0.1, rtol=1e-12)
    assert velocities.shape == experience.shape == (16, 7)


def test_the_initial_velocity_can_be_chosen() -> None:
    fam = Fam(SINGLE, NAMES, init_velocity_mps=0.05)
    np.testing.assert_allclose(fam.velocities(np.full(16, 1.0)), 0.05, rtol=1e-12)


def test_a_trained_ring_on_centres_is_perceived_at_its_label() -> None:
    fam = Fam(SINGLE, NAMES)
    ring = on_centres(SINGLE.tables[0], (0, 1, 2, 0, 3))
    fam.train(ring[None], np.array([T1L]), np.array([0.42]), symmetric=False)
    assert fam.velocities(ring)[T1L] == 0.42
    assert fam.experience(ring)[T1L] == 1.0


def test_inference_is_the_strength_weighted_average_of_fired_rules(single: Fam) -> None:
    ring = random_rings(np.random.default_rng(5), 1)[0]
    explanation = single.explain(ring)
    strengths = np.array([r.strength for r in explanation.rules])
    stored = np.array([r.velocities_mps for r in explanation.rules])  # (fired, 7)
    expected = strengths @ stored / strengths.sum()
    np.testing.assert_allclose(single.velocities(ring), expected, rtol=1e-12)
    np.testing.assert_allclose(explanation.velocities_mps, single.velocities(ring), rtol=1e-15)


@given(ring_values)
@settings(max_examples=30, deadline=None)
def test_rotation_by_sixteen_is_the_identity(multi: Fam, values: list[float]) -> None:
    fam, ring = multi, np.array(values)
    np.testing.assert_array_equal(fam.velocities(ring, rotation=16), fam.velocities(ring))
    np.testing.assert_array_equal(fam.experience(ring, rotation=16), fam.experience(ring))


@given(ring_values, st.integers(0, 15), st.sampled_from(["single", "multi", "designed"]))
@settings(max_examples=40, deadline=None)
def test_rotation_by_k_equals_reading_the_ring_shifted_by_k(
    fams: dict[str, Fam], values: list[float], k: int, name: str
) -> None:
    fam, ring = fams[name], np.array(values)
    shifted = ring[(np.arange(16) + k) % 16]
    np.testing.assert_array_equal(fam.velocities(ring, rotation=k), fam.velocities(shifted))
    velocities, experience = fam.perceive(ring)
    np.testing.assert_allclose(velocities[k], fam.velocities(shifted), rtol=1e-12)
    np.testing.assert_allclose(experience[k], fam.experience(shifted), rtol=1e-12)


@given(ring_values, st.sampled_from(["single", "multi", "designed"]))
@settings(max_examples=30, deadline=None)
def test_the_view_ahead_alone_is_row_zero_of_every_view_bit_for_bit(
    fams: dict[str, Fam], values: list[float], name: str
) -> None:
    fam, ring = fams[name], np.array(values)
    np.testing.assert_array_equal(fam.perceive_ahead(ring), fam.perceive(ring)[0][0])


def test_batch_inference_agrees_with_one_ring_at_a_time(multi: Fam) -> None:
    rings = random_rings(np.random.default_rng(6), 700)  # more than one inference chunk
    batch = multi.velocities(rings, rotation=3)
    assert batch.shape == (700, 7)
    for i in (0, 350, 699):
        np.testing.assert_allclose(batch[i], multi.velocities(rings[i], rotation=3), rtol=1e-12)


def test_sonars_within_an_angle_of_ahead_include_the_edge_ones() -> None:
    assert sorted(sonars_within(np.pi / 4)) == [0, 1, 2, 14, 15]
    assert sorted(sonars_within(np.pi / 2)) == [0, 1, 2, 3, 4, 12, 13, 14, 15]


def test_the_mirror_of_the_mirror_is_the_identity() -> None:
    assert MIRROR[MIRROR].tolist() == list(range(16))
    assert MIRROR[0] == 0 and MIRROR[8] == 8 and MIRROR[4] == 12


@pytest.mark.parametrize("config", [SINGLE, MULTI], ids=lambda c: c.name)
@pytest.mark.parametrize("left", ["T1L", "T2L", "T3L"])
def test_symmetric_training_of_left_equals_training_right_on_the_mirrored_ring(
    config: FamConfig, left: str
) -> None:
    rng = np.random.default_rng(7)
    rings, labels = random_rings(rng, 400), rng.uniform(0, 0.6, 400)
    j = NAMES.index(left)
    on_left = np.full(400, j)
    on_right = np.full(400, len(NAMES) - 1 - j)
    symmetric, by_hand = Fam(config, NAMES), Fam(config, NAMES)
    symmetric.train(rings, on_left, labels, symmetric=True)
    by_hand.train(rings, on_left, labels, symmetric=False)
    by_hand.train(rings[:, MIRROR], on_right, labels, symmetric=False)
    for (v1, e1), (v2, e2) in zip(tables(symmetric), tables(by_hand), strict=True):
        np.testing.assert_array_equal(e1, e2)
        np.testing.assert_array_equal(v1, v2)


def test_without_symmetry_the_mirror_trajectory_stays_untrained() -> None:
    rng = np.random.default_rng(8)
    fam = Fam(SINGLE, NAMES)
    fam.train(random_rings(rng, 100), np.full(100, T1L), np.full(100, 0.3), symmetric=False)
    experience = fam.experience_table(0)
    assert experience[:, T1L].sum() > 0
    assert experience[:, T1R].sum() == 0


def test_symmetric_training_mirrors_the_left_fam_into_the_right_one() -> None:
    rng = np.random.default_rng(9)
    fam = Fam(MULTI, NAMES)
    fam.train(random_rings(rng, 300), np.full(300, T1L), rng.uniform(0, 0.6, 300))
    np.testing.assert_array_equal(fam.velocity_table(T1R), fam.velocity_table(T1L))
    np.testing.assert_array_equal(fam.experience_table(T1R), fam.experience_table(T1L))


def test_symmetric_training_of_t0_also_trains_it_with_the_mirrored_ring() -> None:
    rng = np.random.default_rng(10)
    rings, labels = random_rings(rng, 200), rng.uniform(0, 0.6, 200)
    symmetric, by_hand = Fam(SINGLE, NAMES), Fam(SINGLE, NAMES)
    symmetric.train(rings, np.full(200, T0), labels)
    by_hand.train(rings, np.full(200, T0), labels, symmetric=False)
    by_hand.train(rings[:, MIRROR], np.full(200, T0), labels, symmetric=False)
    np.testing.assert_allclose(symmetric.experience_table(0), by_hand.experience_table(0))
    np.testing.assert_allclose(symmetric.velocity_table(0), by_hand.velocity_table(0))


def test_rebuilding_from_tables_keeps_every_value(multi: Fam) -> None:
    rebuilt = Fam.from_tables(
        MULTI,
        NAMES,
        [v for v, _ in tables(multi)],
        [e for _, e in tables(multi)],
        multi.init_velocity_mps,
    )
    for (v1, e1), (v2, e2) in zip(tables(multi), tables(rebuilt), strict=True):
        np.testing.assert_array_equal(v1, v2)
        np.testing.assert_array_equal(e1, e2)
    ring = random_rings(np.random.default_rng(11), 1)[0]
    np.testing.assert_array_equal(rebuilt.perceive(ring)[0], multi.perceive(ring)[0])


def test_rebuilding_from_tables_of_the_wrong_shape_is_refused() -> None:
    with pytest.raises(BadInput, match="expected"):
        Fam.from_tables(SINGLE, NAMES, [np.zeros((720, 6))], [np.zeros((720, 6))])


def test_tables_are_copies(single: Fam) -> None:
    table = single.velocity_table(0)
    table[:] = 99.0
    assert (single.velocity_table(0) != 99.0).all()


def test_rule_set_indices_unravel_flat_rule_indices() -> None:
    table = SINGLE.tables[0]
    sets = rule_set_indices(table)
    assert sets.shape == (720, 5)
    assert sets[0].tolist() == [0, 0, 0, 0, 0]
    assert sets[-1].tolist() == [4, 3, 2, 2, 3]
    assert np.ravel_multi_index(tuple(sets.T), table.shape).tolist() == list(range(720))


def test_explain_lists_memberships_fired_rules_and_perceptions(single: Fam) -> None:
    table = SINGLE.tables[0]
    ring = on_centres(table, (1, 3, 0, 2, 1))
    front = table.inputs[0]
    ring[list(front.sonars)] = 0.3  # between VN (0.20) and N (0.45)
    explanation = single.explain(ring)
    assert [i.name for i in explanation.inputs] == [i.name for i in table.inputs]
    assert [(s.name, round(s.degree, 12)) for s in explanation.inputs[0].fired] == [
        ("VN", 0.6),
        ("N", 0.4),
    ]
    assert [r.set_names for r in explanation.rules] == [
        ("VN", "F", "N", "F", "N"),
        ("N", "F", "N", "F", "N"),
    ]
    assert [round(r.strength, 12) for r in explanation.rules] == [0.6, 0.4]
    assert explanation.velocities_mps == tuple(single.velocities(ring))
    assert json.dumps(explanation.to_dict())


def test_explain_covers_every_table(multi: Fam) -> None:
    explanation = multi.explain(random_rings(np.random.default_rng(12), 1)[0])
    assert {r.table for r in explanation.rules} == {t.name for t in MULTI.tables}
    assert len(explanation.inputs) == sum(len(t.inputs) for t in MULTI.tables)


def test_a_shipped_configuration_round_trips_through_json() -> None:
    for config in (SINGLE, MULTI):
        assert fam_config_from_json(config.to_json(), NAMES) == config


def bad(config: dict) -> str:
    with pytest.raises(BadInput) as error:
        fam_config_from_json(json.dumps(config), NAMES, "my.json")
    return str(error.value)


def single_dict() -> dict:
    return json.loads(SINGLE.to_json())


def test_a_sonar_outside_the_ring_is_refused() -> None:
    config = single_dict()
    config["tables"][0]["inputs"][1]["sonars"] = [2, 16]
    assert bad(config) == "my.json: table 'all' input 'front-left': sonar 16 is outside 0..15"


def test_a_trajectory_stored_twice_is_refused() -> None:
    config = json.loads(MULTI.to_json())
    config["tables"][0]["trajectories"] = ["T3L", "T0"]
    assert "trajectory 'T0' is already stored by table 'T3L'" in bad(config)


def test_a_trajectory_no_table_stores_is_refused() -> None:
    config = single_dict()
    config["tables"][0]["trajectories"] = list(NAMES[:-1])
    assert bad(config) == "my.json: no table stores trajectory T3R"


def test_an_unknown_trajectory_is_refused() -> None:
    config = single_dict()
    config["tables"][0]["trajectories"] = [*NAMES, "T9X"]
    assert "unknown trajectory 'T9X'" in bad(config)


def test_repeated_set_names_are_refused() -> None:
    config = single_dict()
    config["tables"][0]["inputs"][0]["partition"]["names"] = ["VN", "N", "N", "F", "VF"]
    assert "fuzzy-set names are not unique" in bad(config)


def test_decreasing_centres_are_refused() -> None:
    config = single_dict()
    config["tables"][0]["inputs"][0]["partition"]["centres_m"] = [0.2, 0.1, 0.8, 1.3, 2.0]
    assert "centres must increase" in bad(config)


def test_a_missing_key_is_refused() -> None:
    config = single_dict()
    del config["tables"][0]["inputs"][0]["sonars"]
    assert bad(config) == "my.json: missing key 'sonars'"


def test_text_that_is_not_json_is_refused_with_its_position() -> None:
    with pytest.raises(BadInput, match=r"^my.json:2:1: not JSON"):
        fam_config_from_json('{"name": "x",\n}', NAMES, "my.json")


def test_a_fam_too_large_for_memory_is_refused() -> None:
    big = Partition(tuple(f"s{i}" for i in range(10)), tuple(float(i) for i in range(10)))
    inputs = tuple(FamInput(f"S{s}", (s,), big) for s in range(8))
    config = FamConfig("big", (FamTable("all", inputs, NAMES),))
    with pytest.raises(BadInput, match="rule entries"):
        validate_fam_config(config, NAMES)


def test_training_refuses_readings_that_are_not_numbers_and_labels_that_are_not_finite() -> None:
    rng = np.random.default_rng(11)
    rings, labels = random_rings(rng, 20), rng.uniform(0, 0.6, 20)
    trajectories = rng.integers(0, len(NAMES), 20)
    fam = Fam(SINGLE, NAMES)
    for bad_rings, bad_labels in (
        (np.where(np.arange(16) == 3, np.nan, rings), labels),
        (rings, np.where(np.arange(20) == 5, np.inf, labels)),
        (rings, np.where(np.arange(20) == 5, np.nan, labels)),
    ):
        with pytest.raises(ValueError, match="finite"):
            fam.train(bad_rings, trajectories, bad_labels)
    untouched = tables(Fam(SINGLE, NAMES))
    assert all(
        np.array_equal(a, b) for t, u in zip(tables(fam), untouched, strict=True)
        for a, b in zip(t, u, strict=True)
    )  # fmt: skip
    fam.train(np.where(np.arange(16) == 3, np.inf, rings), trajectories, labels)  # nothing heard


@pytest.mark.parametrize("config", [SINGLE, MULTI, DESIGNED], ids=lambda c: c.name)
def test_each_table_trains_on_its_own_trajectories_rows_in_order(config: FamConfig) -> None:
    fam = Fam(config, NAMES)
    trajectories = np.random.default_rng(12).integers(0, len(NAMES), 500)
    held = [{NAMES.index(n) for n in table.trajectories} for table in config.tables]
    for rows, trajectories_held in zip(fam._rows_by_table(trajectories), held, strict=True):
        expected = np.flatnonzero(np.isin(trajectories, list(trajectories_held)))
        np.testing.assert_array_equal(rows, expected)
