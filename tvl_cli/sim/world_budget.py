"""How large a world this machine can simulate: a world is refused, when it is read, if
learning in it would take more than half the memory the machine (or the container it runs
in, or TVL_MEMORY_MIB) has, rather than at a fixed file size; and if it has more wall
segments than its physics can be built from in seconds.

What a world costs grows with its grid's cells (the coverage floor's lattice, the map's
arrays) and with its wall segments (pymunk's shapes, the sonar's arrays and grid of walls);
the figures per cell and per segment are peaks measured by `benchmarks/large_worlds.py`,
rounded up.
"""

from __future__ import annotations

import os
from pathlib import Path

from tvl_cli.core.errors import BadInput

# Peak bytes a learning process takes for each cell of its world's grid, and for each wall
# segment (benchmarks/large_worlds.py measures both).
BYTES_PER_CELL = 120
BYTES_PER_SEGMENT = 2_500
# The most wall segments a world may have: the physics is built wall by wall, some 15 µs each
# in pymunk's Python, so that more would take minutes to start (a map of scattered pixels,
# each its own four walls, reaches it long before the memory does).
MAX_SEGMENTS = 250_000
# Peak bytes an import takes for each pixel of a map's image: read, classified and coarsened.
BYTES_PER_IMAGE_PIXEL = 64
# The share of the machine's memory a world may take: room for the rest of the process, and
# for the rest of the machine.
MEMORY_SHARE = 0.5
# The environment variable that sets the memory tvl may count on, in MiB.
MEMORY_VARIABLE = "TVL_MEMORY_MIB"
# Where a container's memory limit is kept (cgroup v2, then v1).
_CGROUP_LIMITS = (
    Path("/sys/fs/cgroup/memory.max"),
    Path("/sys/fs/cgroup/memory/memory.limit_in_bytes"),
)


def machine_bytes() -> int:
    """The memory this process may use: the machine's, or its container's limit if less, or
    what the environment's TVL_MEMORY_MIB gives (to share a machine with other work)."""
    given = os.environ.get(MEMORY_VARIABLE)
    if given is not None:
        if not given.isdigit() or int(given) == 0:
            raise BadInput(f"{MEMORY_VARIABLE}={given!r}: expected a whole number of MiB")
        return int(given) << 20
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
    if segments > MAX_SEGMENTS:
        return (
            f"a world of {segments:,} wall segments, over the {MAX_SEGMENTS:,} whose physics "
            "starts in seconds"
        )
    needed, budget = world_bytes(cells, segments), world_budget_bytes()
    if needed <= budget:
        return None
    return (
        f"a world of {cells:,} cells and {segments:,} wall segments needs about "
        f"{_size(needed)} to simulate, over the {_size(budget)} this machine gives a world "
        "(half its memory)"
    )


def _size(count: int) -> str:
    """Bytes in the largest binary unit that keeps a whole number of them."""
    for unit, power in (("GiB", 30), ("MiB", 20)):
        if count >= 2**power:
            return f"{count / 2**power:.1f} {unit}" if power == 30 else f"{count >> power} {unit}"
    return f"{count >> 10} KiB"
