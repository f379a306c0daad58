"""Every tvl file says what it is; a reader refuses anything else in one line naming the file."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
import pytest
from log_samples import open_sample_writer, sample_episode

from tvl_cli import __version__
from tvl_cli.core.errors import BadInput
from tvl_cli.io.hdf5_header import (
    FAM_FORMAT,
    FORMAT_VERSIONS,
    LOG_FORMAT,
    FormatError,
    file_format,
    open_for_reading,
    write_header,
)


def tvl_file(path: Path, file_format: str = LOG_FORMAT, **attrs: object) -> Path:
    with h5py.File(path, "w") as f:
        write_header(f, file_format)
        f.attrs.update(attrs)
    return path


def refusal(path: Path, expected: str = LOG_FORMAT) -> str:
    with pytest.raises(BadInput) as caught:
        open_for_reading(path, expected).close()
    message = str(caught.value)
    assert "\n" not in message
    assert message.startswith(f"{path}: ")
    return message


def test_header_names_format_version_tool_and_time(tmp_path: Path) -> None:
    with h5py.File(tvl_file(tmp_path / "a.h5", FAM_FORMAT, extra=1)) as f:
        assert f.attrs["format"] == "tvl-fam"
        assert f.attrs["format_version"] == FORMAT_VERSIONS["tvl-fam"] == 3
        assert f.attrs["tvl_version"] == __version__
        assert str(f.attrs["created"]).endswith("+00:00")


def test_header_stores_extra_values_as_json_one_key_a_line(tmp_path: Path) -> None:
    value = {"b": 1, "a": [1.5, "x"], "c": [{"d": None}], "e": {}}
    with h5py.File(tmp_path / "a.h5", "w") as f:
        write_header(f, LOG_FORMAT, config=value)
        text = f.attrs["config"]
    assert (
        text == '{\n "a": [1.5, "x"],\n "b": 1,\n "c": [\n  {\n   "d": null\n  }\n ],\n "e": {}\n}'
    )
    assert json.loads(text) == value


def test_a_file_of_the_expected_format_opens(tmp_path: Path) -> None:
    with open_for_reading(tvl_file(tmp_path / "a.h5"), LOG_FORMAT) as f:
        assert f.attrs["format"] == LOG_FORMAT


def test_text_file_is_not_hdf5(tmp_path: Path) -> None:
    path = tmp_path / "notes.h5"
    path.write_text("not a log\n")
    assert refusal(path) == f"{path}: not an HDF5 file"


def test_empty_file_is_named_empty(tmp_path: Path) -> None:
    path = tmp_path / "empty.h5"
    path.write_bytes(b"")
    assert refusal(path) == f"{path}: is empty, not an HDF5 file"


def test_missing_file_is_refused(tmp_path: Path) -> None:
    assert refusal(tmp_path / "gone.h5") == f"{tmp_path / 'gone.h5'}: no such file"


def test_directory_is_refused(tmp_path: Path) -> None:
    assert refusal(tmp_path) == f"{tmp_path}: is a directory, not a file"


def test_another_tvl_format_is_refused_by_name(tmp_path: Path) -> None:
    path = tvl_file(tmp_path / "a.h5", FAM_FORMAT)
    with pytest.raises(FormatError) as caught:
        open_for_reading(path, LOG_FORMAT)
    assert str(caught.value) == f"{path}: is a tvl-fam file, expected a tvl-log"


def test_newer_version_is_refused(tmp_path: Path) -> None:
    path = tvl_file(tmp_path / "a.h5", format_version=3)
    message = refusal(path)
    assert message == f"{path}: format_version 3 is newer than this tvl reads (2)"


def test_hdf5_file_without_format_is_not_a_tvl_file(tmp_path: Path) -> None:
    path = tmp_path / "other.h5"
    with h5py.File(path, "w") as f:
        f["x"] = np.arange(3)
    assert refusal(path) == f"{path}: not a tvl file (no 'format' attribute)"


def test_foreign_format_attribute_is_not_a_tvl_file(tmp_path: Path) -> None:
    path = tmp_path / "other.h5"
    with h5py.File(path, "w") as f:
        f.attrs["format"] = "netcdf"
    assert refusal(path) == f"{path}: not a tvl file (its format is 'netcdf')"


def test_fixed_length_string_format_is_read_like_a_variable_one(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    with h5py.File(path, "w") as f:
        f.attrs["format"] = np.bytes_(b"tvl-log")
        f.attrs["format_version"] = np.int32(1)
    open_for_reading(path, LOG_FORMAT).close()


def test_missing_version_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    with h5py.File(path, "w") as f:
        f.attrs["format"] = LOG_FORMAT
    assert refusal(path) == f"{path}: tvl-log file without an integer 'format_version'"


def test_truncated_file_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "x.h5"
    with open_sample_writer(path) as writer:
        for index in range(30):
            writer.append_episode(sample_episode(index))
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    assert "truncated" in refusal(path)


def test_corrupt_superblock_is_refused(tmp_path: Path) -> None:
    path = tvl_file(tmp_path / "a.h5")
    data = bytearray(path.read_bytes())
    data[8:48] = bytes(40)  # the superblock after the signature
    path.write_bytes(bytes(data))
    assert refusal(path).startswith(f"{path}: corrupt HDF5 file (")


def test_file_format_names_any_tvl_kind(tmp_path: Path) -> None:
    assert file_format(tvl_file(tmp_path / "a.h5", FAM_FORMAT)) == "tvl-fam"


def test_file_format_of_a_plain_hdf5_file_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "other.h5"
    with h5py.File(path, "w"):
        pass
    with pytest.raises(FormatError, match=r"other\.h5: not a tvl file"):
        file_format(path)
