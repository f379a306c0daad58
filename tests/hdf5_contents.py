"""An HDF5 file's datasets by name, to compare two files value for value."""

from __future__ import annotations

from pathlib import Path

import h5py


def datasets(path: Path) -> dict[str, object]:
    """Every dataset's values by name: raw bytes for numbers, the strings for text."""
    found: dict[str, object] = {}

    def visit(name: str, obj: object) -> None:
        if isinstance(obj, h5py.Dataset):
            values = obj[()]
            found[name] = values.tolist() if obj.dtype.kind == "O" else values.tobytes()

    with h5py.File(path, "r") as f:
        f.visititems(visit)
    return found
