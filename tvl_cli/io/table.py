"""Tables of result rows: a JSON-lines journal grown a row at a time, and CSV and Parquet
files written whole."""

from __future__ import annotations

import csv
import errno
import io
import json
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from tvl_cli.io.atomic import atomic_output

Row = dict[str, Any]


# Significant digits of a number in CSV: a measure's noise is far above the sixth digit, and
# the JSON lines (and Parquet) beside a CSV keep every digit.
CSV_DIGITS = 6
# Joins the items of a list of names or numbers in one CSV cell (`near-miss;bump`): a comma
# would need quoting, and the cell is one split away from the list.
CSV_LIST_SEPARATOR = ";"


def csv_text(rows: Sequence[Row]) -> str:
    """Rows as CSV under a header of every column, in the order they first appear: a value
    as a spreadsheet or a CSV reader takes it (`true`/`false`, numbers to CSV_DIGITS
    significant digits, a list of names or numbers joined by CSV_LIST_SEPARATOR), a record
    (`memory`) as a column per field (`memory.kind`), and a list of records (a run's
    `minutes`), a table of its own, left to the JSON. A key a row lacks (another table's
    input) and None are left empty. No rows, no text."""
    if not rows:
        return ""
    flat = [_flat(row) for row in rows]
    records = {key for row in flat for key, value in row.items() if _holds_records(value)}
    out = io.StringIO()
    columns = [key for key in dict.fromkeys(k for row in flat for k in row) if key not in records]
    writer = csv.DictWriter(out, fieldnames=columns, lineterminator="\n", extrasaction="ignore")
    writer.writeheader()
    writer.writerows({key: _cell(value) for key, value in row.items()} for row in flat)
    return out.getvalue()


def _flat(row: Row, prefix: str = "") -> Row:
    """A row with each record's fields as values of their own (`memory.kind`)."""
    flat: Row = {}
    for key, value in row.items():
        if isinstance(value, dict):
            flat.update(_flat(value, f"{prefix}{key}."))
        else:
            flat[f"{prefix}{key}"] = value
    return flat


def _holds_records(value: Any) -> bool:
    return isinstance(value, list) and any(isinstance(v, list | dict) for v in value)


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:.{CSV_DIGITS}g}"
    if isinstance(value, list | tuple):
        return CSV_LIST_SEPARATOR.join(_cell(v) for v in value)
    return str(value)


def append_row(path: Path, row: Row) -> None:
    """Add the row to `path` as one JSON line, in a single write: a kill keeps or loses the
    whole row, and a write the disk cuts short is taken back."""
    append_rows(path, [row])


def append_rows(path: Path, rows: Sequence[Row]) -> None:
    """Add the rows to `path`, a JSON line each, in a single write: a kill keeps or loses
    them all, and a write the disk cuts short is taken back."""
    line = "".join(json.dumps(row, allow_nan=False) + "\n" for row in rows).encode("utf-8")
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o666)
    try:
        start = os.fstat(fd).st_size
        try:
            if os.write(fd, line) != len(line):
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
        except OSError:
            os.ftruncate(fd, start)
            raise
    finally:
        os.close(fd)


def write_csv(path: Path, rows: Sequence[Row]) -> None:
    with atomic_output(path) as temporary:
        temporary.write_text(csv_text(rows), encoding="utf-8")


def write_parquet(path: Path, rows: Sequence[Row]) -> bool:
    """The rows as a Parquet file if pyarrow is installed (it is optional); whether it was."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return False
    with atomic_output(path) as temporary:
        pq.write_table(pa.Table.from_pylist(list(rows)), temporary)
    return True
