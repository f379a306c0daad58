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


def csv_text(rows: Sequence[Row]) -> str:
    """Rows as CSV under a header of every key, in the order keys first appear; a key a row
    lacks (another table's input) and None are left empty, and a list or an object (a run's
    `minutes`) is one cell of JSON. No rows, no text."""
    if not rows:
        return ""
    out = io.StringIO()
    columns = list(dict.fromkeys(key for row in rows for key in row))
    writer = csv.DictWriter(out, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({key: _cell(value) for key, value in row.items()})
    return out.getvalue()


def _cell(value: Any) -> Any:
    return json.dumps(value, allow_nan=False) if isinstance(value, list | dict) else value


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
