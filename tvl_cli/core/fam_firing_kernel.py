"""What the FAM kernels share: an input's fuzzy sets, and the corners of a table's cell."""

from __future__ import annotations

from tvl_cli.core.numba_kernel import inlined


@inlined
def fuzzify(x, p, interior, gap_start, gap_low, gap_width):
    """Lower set index and upper degree of reading x (metres, finite or +inf) in partition p
    (core.fuzzy.StackedPartitions' arrays)."""
    # Counting the inner centres at or below x gives the gap x lies in, clamped to the first
    # and last gap, which is where the shoulders are (NaN pads: no reading compares >= NaN).
    lower = 0
    for c in range(interior.shape[1]):
        if x >= interior[p, c]:
            lower += 1
    gap = lower + gap_start[p]
    upper = (x - gap_low[gap]) / gap_width[gap]
    if upper < 0.0:  # the shoulders
        upper = 0.0
    elif upper > 1.0:
        upper = 1.0
    return lower, upper


@inlined
def add_input(strength, offset, size, upper, stride):
    """Extend the first `size` corners (strengths, rule offsets) by one more input of upper
    degree `upper` and index step `stride`, to 2 * size corners: corner c takes the input's
    lower set as 2c and its upper set as 2c + 1, so the first input is the most significant,
    as core.fam_firing.Firing orders them."""
    for c in range(size - 1, -1, -1):  # from the top, so that each is read before it is written
        s, o = strength[c], offset[c]
        strength[2 * c] = s if s < 1.0 - upper else 1.0 - upper
        offset[2 * c] = o
        strength[2 * c + 1] = s if s < upper else upper
        offset[2 * c + 1] = o + stride
    return 2 * size
