"""Every version's method reads back whole: the current files' one record, and the pieces
older files kept, each read by io.method_records alone."""

from __future__ import annotations

import pytest

from tvl_cli.core.errors import BadInput
from tvl_cli.core.memory import DEFAULT_MEMORY, NO_MEMORY, MemoryConfig
from tvl_cli.core.method import (
    DEFAULT,
    FIELDS,
    LEARNING_FIELDS,
    NOVELTY,
    PAPER,
    describe_record,
    method_record,
)
from tvl_cli.core.robot_config import SONAR_MODELS, RobotConfig
from tvl_cli.io.method_records import current, fam_method, session_method, trace_method

ROBOT = RobotConfig()


def test_a_current_record_reads_back_as_the_method_it_records() -> None:
    for method in (DEFAULT, PAPER):
        read = current(method_record(method), "here")
        assert read.method == method
        assert read.unrecorded == ()


def test_a_current_file_without_its_record_is_refused() -> None:
    with pytest.raises(BadInput, match="here method: not recorded"):
        current(None, "here")


def test_a_session_without_a_rule_or_memory_explored_by_the_papers_rule_through_none() -> None:
    read = session_method(None, {"near_m": 0.16, "decel_mps2": 0.3}, ROBOT, "log")
    assert read.method.exploration == "least-experience"
    assert read.method.memory == NO_MEMORY
    assert (read.method.near_m, read.method.decel_mps2) == (0.16, 0.3)
    # What it did not keep (its margin, among the learning fields) is named, filled with ours.
    assert "margin_m" in read.unrecorded and read.method.margin_m == DEFAULT.margin_m
    assert set(read.unrecorded) <= set(LEARNING_FIELDS)


def test_a_sessions_parameters_give_its_rule_and_memory() -> None:
    parameters = {"explore": NOVELTY, "memory": {"kind": "points", "window_s": 30.0}}
    read = session_method(None, parameters, ROBOT, "log")
    assert read.method.exploration == NOVELTY
    assert read.method.memory == MemoryConfig("points", window_s=30.0, clearing="never")


def test_a_sessions_partial_record_lays_over_its_parameters() -> None:
    record = method_record(PAPER, LEARNING_FIELDS)
    read = session_method(record, {"explore": NOVELTY, "decel_mps2": 9.0}, ROBOT, "log")
    assert all(getattr(read.method, n) == getattr(PAPER, n) for n in LEARNING_FIELDS)
    assert read.unrecorded == ()


def test_a_version_1_fam_reads_the_live_ring_with_its_provenances_labels() -> None:
    provenance = {"training": {"decel_mps2": 0.5, "margin_m": 0.05, "symmetric": True}}
    read = fam_method(None, None, provenance, ROBOT, "FAM")
    assert read.method.memory == NO_MEMORY
    assert (read.method.decel_mps2, read.method.margin_m) == (0.5, 0.05)
    assert set(read.unrecorded) == {"near_m", "exploration"}
    assert "near_m, exploration unrecorded" in describe_record(read.record())


def test_a_version_2_fam_reads_through_its_memory_attribute() -> None:
    memory = DEFAULT_MEMORY.to_dict()
    read = fam_method(None, memory, {"training": {}}, ROBOT, "FAM")
    assert read.method.memory == DEFAULT_MEMORY


def test_a_version_2_fams_sessions_that_differ_are_kept_as_mixed() -> None:
    record = {**method_record(DEFAULT, LEARNING_FIELDS), "sessions_differ_in": ["exploration"]}
    read = fam_method(record, None, {}, ROBOT, "FAM")
    assert read.mixed == ("exploration",)
    assert read.record()["preset"] is None


def test_an_ideal_sonars_robot_says_the_sonar_model_of_an_old_file() -> None:
    ideal = RobotConfig(sonar=SONAR_MODELS["ideal"])
    assert fam_method(None, None, {}, ideal, "FAM").method.sonar == "ideal"


def test_an_old_trace_reads_its_reflexes_and_memory_from_its_parameters() -> None:
    parameters = {"reflexes": ["bump"], "memory": {"kind": "patches"}}
    read = trace_method(None, parameters, ROBOT, "trace")
    assert read.method.reflexes == ("bump",)
    assert read.method.memory.kind == "patches"
    known = {"reflexes", "memory", "sonar", "labels", "label_ceiling", "label_ceiling_radius_m"}
    assert set(read.unrecorded) == set(FIELDS) - known
    assert read.method.labels == "bump"  # every file before the heard labels
    assert read.method.label_ceiling == 1.0  # and before labels ran past the top speed
    assert read.method.label_ceiling_radius_m is None


def test_a_malformed_old_memory_names_the_file() -> None:
    with pytest.raises(BadInput, match="log: unknown echo memory setting 'x'"):
        session_method(None, {"memory": {"x": 1}}, ROBOT, "log")
