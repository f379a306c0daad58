"""Result tables: one whole JSON line a row, CSV with a run's per-minute list in one cell,
and Parquet when pyarrow is there."""

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


def test_csv_leaves_none_empty_and_holds_a_list_as_json() -> None:
    read = list(csv.DictReader(io.StringIO(csv_text(ROWS))))
    assert [row["goal"] for row in read] == ["", "1.0,2.5"]
    assert json.loads(read[0]["minutes"]) == ROWS[0]["minutes"]
    assert csv_text([]) == ""


def test_parquet_holds_the_rows(tmp_path: Path) -> None:
    parquet = pytest.importorskip("pyarrow.parquet")
    assert write_parquet(tmp_path / "results.parquet", ROWS)
    assert parquet.read_table(tmp_path / "results.parquet").to_pylist() == ROWS
