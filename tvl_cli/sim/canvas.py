"""A world being drawn: a grid of map characters and header lines, turned into a world file."""

from __future__ import annotations

import numpy as np

from tvl_cli.sim.worldheader import DEFAULT_CELL_M, FORMAT_VERSION

CELL_M = DEFAULT_CELL_M


class Canvas:
    """A grid of map characters, top row first, with a `#` border; plus extra header lines."""

    def __init__(self, cols: int, rows: int) -> None:
        self.grid = np.full(
            (rows, cols), ".", dtype="<U1"
        )  # (rows, cols) characters, top row first
        self.grid[[0, -1], :] = "#"
        self.grid[:, [0, -1]] = "#"
        self.header: list[str] = []

    @property
    def rows(self) -> int:
        return int(self.grid.shape[0])

    @property
    def cols(self) -> int:
        return int(self.grid.shape[1])

    def cell(self, x_frac: float, y_frac: float) -> tuple[int, int]:
        """(row, column) of the cell at a fraction of the width and height from bottom-left."""
        return self.rows - 1 - int(y_frac * self.rows), int(x_frac * self.cols)

    def centre_m(self, r: int, c: int) -> tuple[float, float]:
        return (c + 0.5) * CELL_M, (self.rows - r - 0.5) * CELL_M

    def disc(self, x_m: float, y_m: float, r_m: float) -> None:
        self.header.append(f"disc: {x_m:g} {y_m:g} {r_m:g}")

    def text(self, kind: str, about: str, command: str, name: str | None = None) -> str:
        """The world file: what made it, the header, then the map; named `name`, else for
        its kind."""
        return "\n".join(
            [
                f"; {kind}: {about}",
                f"; made by: {command}",
                f"version: {FORMAT_VERSION}",
                f"name: {name or kind}",
                f"cell: {CELL_M:g}",
                *self.header,
                "",
                *("".join(row) for row in self.grid),
                "",
            ]
        )
