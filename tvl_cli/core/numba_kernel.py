"""The decorators every compiled hot loop is built with. Each numba kernel is a module named
`*_kernel.py` beside the concept it computes for (`sim/ring_kernel.py` for the sonar ring,
`core/fam_perception_kernel.py` for the FAM); the tests compare each with its plain numpy
reference (tests/kernel_references/) on real worlds, rings and exemplars.

A kernel is compiled the first time it runs and cached on disk: in `__pycache__` beside its
module, or, where the package directory is read-only, in the user's cache directory;
`NUMBA_CACHE_DIR` chooses another. The modules that call kernels import them when they are
first built, never at their own import, so that no command's `--help` loads numba.
"""

from __future__ import annotations

import numba

# IEEE arithmetic exactly as numpy does it (no fast-math, which would reorder sums and change
# bits), and numpy's error model: a division by zero gives inf or nan, as in the references,
# instead of raising. (Kernels compare numbers themselves rather than call min() and max(),
# whose compiled versions would add to the first run's compilation.)
kernel = numba.njit(cache=True, error_model="numpy")
# The same for a small helper compiled into each kernel that calls it: its array arguments
# are then not counted in and out of every call. A helper of numbers alone is a `kernel`
# instead: it compiles once, where an inlined one is copied into every place that calls it
# and analysed again there (numba's inlining was a third of the ring kernel's first compile), and
# the compiler still folds its calls in, with nothing to count.
inlined = numba.njit(cache=True, error_model="numpy", inline="always")
