"""The FAM file: a round trip keeps everything, axes are labelled, the same FAM gives the
same bytes, and anything else is refused naming the file."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest
from method_samples import LIVE_RING

from tvl_cli import __version__
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import (
    DESIGNED,
    MULTI,
    SINGLE,
    FamConfig,
    FamInput,
    FamTable,
    Partition,
)
from tvl_cli.core.robot_config import RobotConfig as Robot
from tvl_cli.io import famfile, hdf5_header
from tvl_cli.io.famfile import read_fam, write_fam
from tvl_cli.io.hdf5_header import FormatError

ROBOT = Robot()
NAMES = [t.name for t in ROBOT.trajectories]
PROVENANCE: dict[str, Any] = {
    "logs": [{"path": "logs/a.h5", "sha256": "ab" * 32, "sessions": ["0000", "0001"]}],
    "decel_mps2": 0.5,
    "margin_m": 0.05,
    "symmetric": True,
    "init_velocity_mps": 0.2,
}


def trained(config: FamConfig, seed: int = 0, count: int = 2000) -> Fam:
    rng = np.random.default_rng(seed)
    fam = Fam(config, NAMES, init_velocity_mps=0.2)
    rings = rng.uniform(0.15, 4.0, (count, 16))  # (count, 16) m
    trajectories = rng.integers(0, 7, count)
    # Labels as learning makes them: from standing still to each trajectory's top speed.
    top = np.array(ROBOT.v_max_mps)[trajectories]
    fam.train(rings, trajectories, rng.uniform(0.0, 1.0, count) * top)
    return fam


def written(path: Path, fam: Fam) -> Path:
    write_fam(path, fam, robot_config=ROBOT, method=LIVE_RING, provenance=PROVENANCE)
    return path


def contents(path: Path) -> dict[str, Any]:
    """Every attribute and dataset value in the file, by path, but the creation time."""
    found: dict[str, Any] = {}

    def visit(name: str, obj: h5py.HLObject) -> None:
        for key, value in obj.attrs.items():
            if key not in ("created", "DIMENSION_LIST", "REFERENCE_LIST"):
                found[f"{name}@{key}"] = np.asarray(value).tolist()
        if isinstance(obj, h5py.Dataset):
            found[name] = obj[()].tolist()
            found[f"{name}:dims"] = [[s.name for s in d.values()] for d in obj.dims]

    with h5py.File(path) as f:
        visit("/", f)
        f.visititems(visit)
    return found


@pytest.mark.parametrize("config", [SINGLE, MULTI, DESIGNED], ids=["single", "multi", "designed"])
def test_round_trip_keeps_every_table_value(tmp_path: Path, config: FamConfig) -> None:
    fam = trained(config)
    back = read_fam(written(tmp_path / "f.h5", fam)).fam
    assert back.config == fam.config
    assert back.trajectory_names == fam.trajectory_names
    assert back.init_velocity_mps == 0.2
    for t in range(len(config.tables)):
        np.testing.assert_array_equal(back.velocity_table(t), fam.velocity_table(t))
        np.testing.assert_array_equal(back.experience_table(t), fam.experience_table(t))


def test_round_trip_keeps_robot_provenance_and_version(tmp_path: Path) -> None:
    read = read_fam(written(tmp_path / "f.h5", trained(SINGLE)))
    assert read.robot_config == ROBOT
    assert read.provenance == PROVENANCE
    assert read.tvl_version == __version__
    assert read.created.endswith("+00:00")


def test_reloaded_fam_perceives_identically(tmp_path: Path) -> None:
    fam = trained(MULTI)
    back = read_fam(written(tmp_path / "f.h5", fam)).fam
    rings = np.random.default_rng(5).uniform(0.15, 4.0, (50, 16))
    for rotation in (0, 3, 11):
        np.testing.assert_array_equal(
            back.velocities(rings, rotation), fam.velocities(rings, rotation)
        )
        np.testing.assert_array_equal(
            back.experience(rings, rotation), fam.experience(rings, rotation)
        )


def test_rewriting_a_read_fam_keeps_every_dataset_and_attribute(tmp_path: Path) -> None:
    first = written(tmp_path / "a.h5", trained(SINGLE))
    read = read_fam(first)
    second = tmp_path / "b.h5"
    write_fam(
        second,
        read.fam,
        robot_config=read.robot_config,
        method=read.method,
        provenance=read.provenance,
    )
    assert contents(second) == contents(first)


def test_same_fam_gives_the_same_bytes(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(hdf5_header, "utc_now", lambda: "2000-01-01T00:00:00+00:00")
    a = written(tmp_path / "a.h5", trained(MULTI))
    b = written(tmp_path / "b.h5", trained(MULTI))
    assert a.read_bytes() == b.read_bytes()


def test_tables_are_stored_with_one_axis_per_input(tmp_path: Path) -> None:
    path = written(tmp_path / "f.h5", trained(SINGLE))
    with h5py.File(path) as f:
        velocity = f["fams/all/velocity"]
        assert velocity.shape == (5, 4, 3, 3, 4, 7)
        assert velocity.attrs["units"] == "m/s"
        assert f["fams/all/experience"].attrs["units"] == "1"
        labels = [d.label for d in velocity.dims]
        assert labels == [
            "front",
            "front-left",
            "rear-left",
            "rear-right",
            "front-right",
            "trajectory",
        ]


def test_axes_carry_set_centres_and_names_as_dimension_scales(tmp_path: Path) -> None:
    path = written(tmp_path / "f.h5", trained(SINGLE))
    with h5py.File(path) as f:
        dims = f["fams/all/velocity"].dims
        front = dims[0][0]
        np.testing.assert_array_equal(front[()], SINGLE.tables[0].inputs[0].partition.centres_m)
        assert list(front.attrs["set_names"]) == ["VN", "N", "M", "F", "VF"]
        assert front.attrs["units"] == "m"
        assert list(front.attrs["sonars"]) == [15, 0, 1]
        assert [n.decode() for n in dims[5][0][()]] == NAMES


def test_each_multi_table_has_its_own_group(tmp_path: Path) -> None:
    path = written(tmp_path / "f.h5", trained(MULTI))
    with h5py.File(path) as f:
        assert sorted(f["fams"]) == sorted(t.name for t in MULTI.tables)
        assert f["fams/T1L/velocity"].shape == (*MULTI.tables[2].shape, 1)


def test_root_attributes_describe_the_file(tmp_path: Path) -> None:
    path = written(tmp_path / "f.h5", trained(SINGLE))
    with h5py.File(path) as f:
        attrs = f.attrs
        assert attrs["format"] == "tvl-fam" and attrs["format_version"] == 3
        assert FamConfig.from_dict(json.loads(attrs["config"])) == SINGLE
        assert Robot.from_dict(json.loads(attrs["robot_config"])) == ROBOT
        assert json.loads(attrs["provenance"]) == PROVENANCE
        assert attrs["init_velocity_mps"] == 0.2
        assert list(attrs["trajectories"]) == NAMES


def test_failed_write_keeps_the_old_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = written(tmp_path / "f.h5", trained(SINGLE))
    before = path.read_bytes()

    def fail(*args: object) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(famfile, "_write_table", fail)
    with pytest.raises(OSError, match="disk full"):
        written(path, trained(SINGLE, seed=1))
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["f.h5"]


def test_a_table_name_hdf5_cannot_hold_is_refused(tmp_path: Path) -> None:
    table = SINGLE.tables[0]
    config = FamConfig("odd", (FamTable("a/b", table.inputs, table.trajectories),))
    with pytest.raises(BadInput, match="table name 'a/b'"):
        written(tmp_path / "f.h5", Fam(config, NAMES))
    assert not (tmp_path / "f.h5").exists()


def test_fam_for_another_robot_is_a_programming_error(tmp_path: Path) -> None:
    fam = Fam(SINGLE, NAMES)
    robot = Robot(trajectories=tuple(reversed(ROBOT.trajectories)))
    with pytest.raises(ValueError, match="not the robot's"):
        write_fam(tmp_path / "f.h5", fam, robot_config=robot, method=LIVE_RING, provenance={})


def test_reading_a_log_as_a_fam_is_refused_by_name(tmp_path: Path) -> None:
    path = tmp_path / "log.h5"
    with h5py.File(path, "w") as f:
        hdf5_header.write_header(f, hdf5_header.LOG_FORMAT)
    with pytest.raises(FormatError, match=r"log\.h5: is a tvl-log file, expected a tvl-fam"):
        read_fam(path)


def test_table_of_the_wrong_shape_is_refused_naming_the_file(tmp_path: Path) -> None:
    path = written(tmp_path / "f.h5", trained(SINGLE))
    with h5py.File(path, "r+") as f:
        del f["fams/all/experience"]
        f["fams/all/experience"] = np.zeros((5, 4, 3, 3, 7))
    with pytest.raises(FormatError, match=r"f\.h5: /fams/all/experience has shape"):
        read_fam(path)


def test_missing_table_is_refused_naming_the_file(tmp_path: Path) -> None:
    path = written(tmp_path / "f.h5", trained(MULTI))
    with h5py.File(path, "r+") as f:
        del f["fams/T2R"]
    with pytest.raises(FormatError, match=r"f\.h5: corrupt tvl-fam"):
        read_fam(path)


def test_malformed_configuration_is_refused_naming_the_file(tmp_path: Path) -> None:
    path = written(tmp_path / "f.h5", trained(SINGLE))
    with h5py.File(path, "r+") as f:
        f.attrs["config"] = '{"name": "x"'
    with pytest.raises(FormatError, match=r"f\.h5: /@config is not valid JSON"):
        read_fam(path)


def test_negative_experience_is_refused_naming_the_file(tmp_path: Path) -> None:
    path = written(tmp_path / "f.h5", trained(SINGLE))
    with h5py.File(path, "r+") as f:
        f["fams/all/experience"][0, 0, 0, 0, 0, 0] = -1.0
    with pytest.raises(FormatError, match=r"f\.h5: table 'all'"):
        read_fam(path)


def test_configuration_with_a_two_set_input_round_trips(tmp_path: Path) -> None:
    sets = Partition(("N", "F"), (0.3, 1.0))
    inputs = (FamInput("left", (4,), sets), FamInput("right", (12,), sets))
    config = FamConfig("tiny", (FamTable("all", inputs, tuple(NAMES)),))
    fam = trained(config)
    back = read_fam(written(tmp_path / "f.h5", fam)).fam
    np.testing.assert_array_equal(back.velocity_table(0), fam.velocity_table(0))
