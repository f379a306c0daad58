"""Result tables: one whole JSON line a row; CSV of flat values as a CSV reader takes them
(true/false, six significant digits, lists joined, records a column a field, tables of
records left to the JSON); and Parquet when pyarrow is there."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import pytest

from tvl_cli.io.table import append_row, csv_text, write_parquet

ROWS = [
    {"world": "square", "threshold": 0.9, "goal": None, "minutes": [{"minute": 0, "sim_s": 30.0}]},
    {"world": "circle", "threshold": 0.7, "goal": "1.0,2.5", "minutes": []},
]


def test_each_appended_row_is_one_json_line(tmp_path: Path) -> None:
    journal = tmp_path / "results.jsonl"
    for row in ROWS:
        append_row(journal, row)
    assert [json.loads(line) for line in journal.read_text().splitlines()] == ROWS


def test_csv_leaves_none_empty_and_a_table_of_records_to_the_json() -> None:
    read = list(csv.DictReader(io.StringIO(csv_text(ROWS))))
    assert [row["goal"] for row in read] == ["", "1.0,2.5"]
    assert "minutes" not in read[0]
    assert csv_text([]) == ""


def test_csv_values_read_as_a_csv_reader_takes_them() -> None:
    row = {
        "goal_reached": False,
        "online": True,
        "distance_m": 24.524973660703996,
        "sim_s": 60.0,
        "delta_v": 6.412345678e-06,
        "seed": 3,
        "reflexes": ["near-miss", "bump"],
        "goal": [3.5, 2.0],
        "memory": {"kind": "patches", "window_s": 20.0},
    }
    text = csv_text([row])
    (read,) = csv.DictReader(io.StringIO(text))
    assert read == {
        "goal_reached": "false",
        "online": "true",
        "distance_m": "24.525",
        "sim_s": "60",
        "delta_v": "6.41235e-06",
        "seed": "3",
        "reflexes": "near-miss;bump",
        "goal": "3.5;2",
        "memory.kind": "patches",
        "memory.window_s": "20",
    }
    assert '"' not in text  # no cell needs quoting


def test_parquet_holds_the_rows(tmp_path: Path) -> None:
    parquet = pytest.importorskip("pyarrow.parquet")
    assert write_parquet(tmp_path / "results.parquet", ROWS)
    assert parquet.read_table(tmp_path / "results.parquet").to_pylist() == ROWS
