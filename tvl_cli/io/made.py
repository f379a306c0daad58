"""What a command made on the file system, to take back when it fails before anything it
made is worth keeping: a command refused late leaves no empty folder behind."""

from __future__ import annotations

from pathlib import Path

from tvl_cli.core.errors import BadInput


class Made:
    """The folders and files made so far, oldest first."""

    def __init__(self) -> None:
        self._paths: list[Path] = []

    def folder(self, path: Path) -> None:
        """Make the folder `path` and each missing above it; BadInput naming it if it cannot
        be made."""
        missing = [p for p in (path, *path.parents) if not p.exists()]
        try:
            path.mkdir(parents=True, exist_ok=True)
        except OSError as error:
            raise BadInput(f"{path}: cannot make the folder ({error.strerror})") from None
        self._paths += reversed(missing)

    def file(self, path: Path) -> None:
        """Remember a file made at `path`."""
        self._paths.append(path)

    def take_back(self) -> None:
        """Remove what was made, newest first: its files, and its folders once empty again
        (a folder something else has put a file in stays, with what leads to it)."""
        for path in reversed(self._paths):
            try:
                if path.is_dir():
                    path.rmdir()
                else:
                    path.unlink(missing_ok=True)
            except OSError:
                continue
        self._paths.clear()
