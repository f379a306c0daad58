"""How large a world this machine can simulate: a world is refused, when it is read, if
learning in it would take more than half the memory the machine (or the container it runs
in) has, rather than at a fixed file size.

What a world costs grows with its grid's cells (the coverage floor's lattice, the map's
arrays) and with its wall segments (pymunk's shapes, the sonar's arrays and grid of walls);
the figures per cell and per segment are peaks measured by `benchmarks/large_worlds.py`,
rounded up.
"""

from __future__ import annotations

import os
from pathlib import Path

# Peak bytes a learning process takes for each cell of its world's grid, and for each wall
# segment (benchmarks/large_worlds.py measures both).
BYTES_PER_CELL = 120
BYTES_PER_SEGMENT = 2_500
# Peak bytes an import takes for each pixel of a map's image: read, classified and coarsened.
BYTES_PER_IMAGE_PIXEL = 64
# The share of the machine's memory a world may take: room for the rest of the process, and
# for the rest of the machine.
MEMORY_SHARE = 0.5
# Where a container's memory limit is kept (cgroup v2, then v1).
_CGROUP_LIMITS = (
    Path("/sys/fs/cgroup/memory.max"),
    Path("/sys/fs/cgroup/memory/memory.limit_in_bytes"),
)


def machine_bytes() -> int:
    """The memory this process may use: the machine's, or its container's limit if less."""
    total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    for limit in _CGROUP_LIMITS:
        try:
            text = limit.read_text().strip()
        except OSError:
            continue
        if text.isdigit():
            total = min(total, int(text))
    return total


def world_budget_bytes() -> int:
    """The memory a world may take to simulate."""
    return int(machine_bytes() * MEMORY_SHARE)


def max_image_pixels() -> int:
    """The most pixels of a map's image worth reading."""
    return world_budget_bytes() // BYTES_PER_IMAGE_PIXEL


def max_file_bytes() -> int:
    """The largest world file worth reading: each character at most a cell."""
    return world_budget_bytes() // BYTES_PER_CELL


def world_bytes(cells: int, segments: int) -> int:
    """The peak memory learning in a world of this many grid cells and wall segments takes."""
    return cells * BYTES_PER_CELL + segments * BYTES_PER_SEGMENT


def over_budget(cells: int, segments: int) -> str | None:
    """Why a world of this many cells and segments is too large for this machine, or None."""
    needed, budget = world_bytes(cells, segments), world_budget_bytes()
    if needed <= budget:
        return None
    return (
        f"a world of {cells:,} cells and {segments:,} wall segments needs about "
        f"{_size(needed)} to simulate, over the {_size(budget)} this machine gives a world "
        f"(half its memory); use a coarser or smaller map"
    )


def _size(count: int) -> str:
    """Bytes in the largest binary unit that keeps a whole number of them."""
    for unit, power in (("GiB", 30), ("MiB", 20)):
        if count >= 2**power:
            return f"{count / 2**power:.1f} {unit}" if power == 30 else f"{count >> power} {unit}"
    return f"{count >> 10} KiB"
