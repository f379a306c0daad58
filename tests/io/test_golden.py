"""Files written by every format version stay readable: the committed golden files read back
as the constants they were made from."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path
from types import ModuleType

import h5py
import numpy as np
from log_samples import assert_same_episode

from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.logreader import read_log


def load_golden() -> ModuleType:
    path = Path(__file__).parents[1] / "data" / "make_golden.py"
    spec = importlib.util.spec_from_file_location("make_golden", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


GOLDEN = load_golden()


def test_golden_log_sessions_keep_their_settings() -> None:
    log = read_log(GOLDEN.GOLDEN_LOG)
    assert [s.name for s in log.sessions] == ["0000", "0001"]
    assert [s.seed for s in log.sessions] == list(GOLDEN.SEEDS)
    for session in log.sessions:
        assert session.world_name == "golden"
        assert session.world_text == GOLDEN.WORLD_TEXT
        assert session.parameters == GOLDEN.PARAMETERS
        assert session.fam_config == SINGLE
        assert [t.name for t in session.robot_config.trajectories] == list(GOLDEN.NAMES)
        assert session.status == "finished"
        assert session.tvl_version == "0.1.0"


def test_golden_log_episodes_read_back_exactly() -> None:
    log = read_log(GOLDEN.GOLDEN_LOG)
    for session, expected in zip(log.sessions, GOLDEN.golden_episodes(), strict=True):
        episodes = session.episodes()
        assert len(episodes) == len(expected)
        for read, written in zip(episodes, expected, strict=True):
            assert_same_episode(read, written)


def test_golden_log_minutes_read_back_exactly() -> None:
    first, second = read_log(GOLDEN.GOLDEN_LOG).sessions
    np.testing.assert_array_equal(first.minutes, np.array(GOLDEN.MINUTES))
    assert second.minutes.shape == (0, 5)


def test_golden_fam_reads_back_its_tables_and_provenance() -> None:
    read = read_fam(GOLDEN.GOLDEN_FAM)
    velocity, experience = GOLDEN.golden_tables()
    assert read.fam.config == GOLDEN.TINY
    assert read.fam.init_velocity_mps == GOLDEN.INIT_VELOCITY_MPS
    np.testing.assert_array_equal(read.fam.velocity_table(0), velocity)
    np.testing.assert_array_equal(read.fam.experience_table(0), experience)
    assert read.provenance == GOLDEN.PROVENANCE
    assert read.tvl_version == "0.1.0"


def test_golden_fam_perceives_a_ring_on_set_centres_as_its_rule() -> None:
    fam = read_fam(GOLDEN.GOLDEN_FAM).fam
    ring = np.full(16, 1.0)  # every input on its F centre: rule (F, F), flat index 3
    ring[[3, 4]] = 0.3  # left input on its N centre: rule (N, F), flat index 1
    velocity, _ = GOLDEN.golden_tables()
    np.testing.assert_allclose(fam.velocities(ring), velocity[1], rtol=0, atol=1e-12)


def test_golden_fam_of_version_1_reads_the_live_ring() -> None:
    assert read_fam(GOLDEN.GOLDEN_FAM).method.memory == NO_MEMORY


def test_golden_fam_of_version_2_reads_back_its_memory_and_tables() -> None:
    read = read_fam(GOLDEN.GOLDEN_FAM_V2)
    assert read.method.memory == GOLDEN.READ_MEMORY
    velocity, experience = GOLDEN.golden_tables()
    np.testing.assert_array_equal(read.fam.velocity_table(0), velocity)
    np.testing.assert_array_equal(read.fam.experience_table(0), experience)
    assert read.provenance == GOLDEN.PROVENANCE


def test_golden_log_of_version_1_reads_its_method_from_its_parameters() -> None:
    for session in read_log(GOLDEN.GOLDEN_LOG).sessions:
        # Its parameters gave the labels' rate alone; the rest is ours, named unrecorded.
        assert session.method.decel_mps2 == GOLDEN.PARAMETERS["decel_mps2"]
        assert session.method.memory == NO_MEMORY
        assert "margin_m" in session.made_by.unrecorded


def test_golden_files_of_the_current_versions_keep_their_method_whole() -> None:
    log = read_log(GOLDEN.GOLDEN_LOG_V2)
    for session, expected in zip(log.sessions, GOLDEN.golden_episodes(), strict=True):
        assert session.method == GOLDEN.METHOD
        assert session.made_by.unrecorded == ()
        for read, written in zip(session.episodes(), expected, strict=True):
            assert_same_episode(read, written)
    fam = read_fam(GOLDEN.GOLDEN_FAM_V3)
    assert fam.method == GOLDEN.METHOD
    assert fam.made_by.unrecorded == ()
    assert fam.provenance == GOLDEN.PROVENANCE_V3
    velocity, _ = GOLDEN.golden_tables()
    np.testing.assert_array_equal(fam.fam.velocity_table(0), velocity)


def test_files_of_the_current_versions_keep_no_piece_of_their_method_beside_it() -> None:
    with h5py.File(GOLDEN.GOLDEN_FAM_V3) as f:
        assert "memory" not in f.attrs
        training = json.loads(f.attrs["provenance"])["training"]
        assert not {"decel_mps2", "margin_m"} & set(training)
    with h5py.File(GOLDEN.GOLDEN_LOG_V2) as f:
        for group in f["sessions"].values():
            parameters = json.loads(group.attrs["parameters"])
            assert not {"memory", "explore", "near_m", "decel_mps2", "margin_m"} & set(parameters)
            assert json.loads(group.attrs["method"])["memory"] == GOLDEN.MEMORY
