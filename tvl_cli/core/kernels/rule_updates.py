"""Training's rule updates (paper eq. 1-2) of one table, and the change of velocity they made
(eq. 4's ΔV): bit for bit what `rule_updates_reference` computes.

Sums are added in numpy's order: each chunk of exemplars corner by corner, exemplar by
exemplar, into sums of its own (as np.bincount did), which are then added to the batch's.
ΔV is summed in numpy's pairwise order over every velocity entry of the FAM, the untouched
ones adding nothing, so that logs keep the bits they were written with.
"""

from __future__ import annotations

import numpy as np

from tvl_cli.core.kernels import kernel
from tvl_cli.core.kernels.firing import fuzzify

# np.add.reduce sums blocks of at most this many values with 8 running sums, and halves
# longer runs (numpy's pairwise summation).
_PAIRWISE_BLOCK = 128
_UNROLL = 8
# Runs waiting to be summed at once: three for each level of halving, of which a vector of
# 2^63 entries has fewer than 64.
_MAX_RUNS = 3 * 64


@kernel
def train_table(
    readings, velocities_mps, rows, columns, pass_ends, pass_sonars, partitions, strides,
    chunk_rows, lookup, first_row, table_columns, weighted_sum, scratch,
):  # fmt: skip
    """Add exemplars to one table; the entries it recomputed (K,), in the order first met,
    and the absolute change of each one's velocity (K,) m/s.

    readings (N * 16,) metres: the rings, row after row; velocities_mps (N,) their labels.
    Pass p trains exemplars rows[pass_ends[p - 1]:pass_ends[p]] into the table's columns
    columns[...] (same slice), reading its n inputs from the sonar groups pass_sonars[p]
    (g, n) (a symmetric pass reads the mirrored ring). partitions: core.fuzzy.StackedPartitions'
    (interior_m, gap_start, gap_low_m, gap_width_m) of the n inputs; strides (n,): each input's
    entry step. chunk_rows: exemplars summed apart before joining the batch's sums.
    lookup (2 cols, R): velocity rows 0 .. cols - 1, experience rows cols .. 2 cols - 1, the
    table's rules from first_row on. weighted_sum (R_t * traj_t,): the table's sums of w * v,
    entry = rule * traj_t + column, traj_t = table_columns. scratch (4, R_t * traj_t): zeros,
    and left zero.
    """
    interior, gap_start, gap_low, gap_width = partitions
    passes, groups, inputs = pass_sonars.shape
    corners = 2**inputs
    entries = weighted_sum.shape[0]
    count = readings.shape[0] // velocities_mps.shape[0]
    lookup_columns = lookup.shape[0] // 2
    batch_w, batch_wv, chunk_w, chunk_wv = scratch[0], scratch[1], scratch[2], scratch[3]
    offset = np.zeros(corners, dtype=np.intp)  # (C,) each corner's entry, from the lowest
    for c in range(corners):
        for i in range(inputs):
            if (c >> (inputs - 1 - i)) & 1:
                offset[c] += strides[i]
    most = min(chunk_rows, rows.shape[0])
    lowest = np.empty(most, dtype=np.intp)  # (M,) each exemplar's lowest corner's entry
    upper = np.empty((most, inputs))  # (M, n) its upper degree in each input
    met = np.empty(min(entries, rows.shape[0] * corners), dtype=np.intp)  # entries the batch met
    met_count = 0
    chunk_met = np.empty(min(entries, most * corners), dtype=np.intp)
    start = 0
    for p in range(passes):
        for chunk_start in range(start, pass_ends[p], chunk_rows):
            chunk = rows[chunk_start : min(chunk_start + chunk_rows, pass_ends[p])]
            for m in range(chunk.shape[0]):
                ring = chunk[m] * count
                entry = columns[chunk_start + m]
                for i in range(inputs):
                    x = readings[ring + pass_sonars[p, 0, i]]
                    for g in range(1, groups):
                        x = min(x, readings[ring + pass_sonars[p, g, i]])
                    lower, degree = fuzzify(x, i, interior, gap_start, gap_low, gap_width)
                    upper[m, i] = degree
                    entry += lower * strides[i]
                lowest[m] = entry
            chunk_count = 0
            for c in range(corners):
                for m in range(chunk.shape[0]):
                    w = 1.0
                    for i in range(inputs):
                        bit = (c >> (inputs - 1 - i)) & 1
                        w = min(w, upper[m, i] if bit else 1.0 - upper[m, i])
                    if w == 0.0:  # adds nothing to any sum
                        continue
                    at = lowest[m] + offset[c]
                    if chunk_w[at] == 0.0:
                        chunk_met[chunk_count] = at
                        chunk_count += 1
                    chunk_w[at] += w
                    chunk_wv[at] += w * velocities_mps[chunk[m]]
            for k in range(chunk_count):
                at = chunk_met[k]
                if batch_w[at] == 0.0:
                    met[met_count] = at
                    met_count += 1
                batch_w[at] += chunk_w[at]
                batch_wv[at] += chunk_wv[at]
                chunk_w[at] = chunk_wv[at] = 0.0
        start = pass_ends[p]
    touched = met[:met_count]
    change = np.empty(met_count)  # (K,) m/s
    for k in range(met_count):
        at = touched[k]
        rule, column = first_row + at // table_columns, at % table_columns
        experience = lookup[lookup_columns + column, rule] + batch_w[at]
        weighted_sum[at] += batch_wv[at]
        velocity = weighted_sum[at] / experience
        change[k] = abs(velocity - lookup[column, rule])
        lookup[column, rule] = velocity
        lookup[lookup_columns + column, rule] = experience
        batch_w[at] = batch_wv[at] = 0.0
    return touched, change


@kernel
def summed_change(entries, change, total):
    """np.add.reduce of the (total,) vector that holds change (K,) at entries (K,) (in
    increasing order) and 0 elsewhere, added in numpy's pairwise order: a run longer than a
    block is split in two at a multiple of 8 near its middle, and the halves' sums added; a
    block is summed with 8 running sums; a run of zeros sums to 0 whatever its grouping."""
    # Runs still to sum, depth first, left before right: each one's start and length, its
    # first entry and the entry after its last, and whether its halves' sums wait on the value
    # stack to be added.
    run_start = np.empty(_MAX_RUNS, dtype=np.intp)
    run_length = np.empty(_MAX_RUNS, dtype=np.intp)
    run_first = np.empty(_MAX_RUNS, dtype=np.intp)
    run_last = np.empty(_MAX_RUNS, dtype=np.intp)
    halves_summed = np.empty(_MAX_RUNS, dtype=np.bool_)
    run_start[0], run_length[0], run_first[0], run_last[0] = 0, total, 0, entries.shape[0]
    halves_summed[0] = False
    pending = 1
    sums = np.empty(_MAX_RUNS)  # the value stack
    summed = 0
    block = np.zeros(_PAIRWISE_BLOCK)
    while pending:
        pending -= 1
        start, n = run_start[pending], run_length[pending]
        first, last = run_first[pending], run_last[pending]
        if halves_summed[pending]:
            summed -= 1
            sums[summed - 1] += sums[summed]
        elif first == last:
            sums[summed] = 0.0
            summed += 1
        elif n <= _PAIRWISE_BLOCK:
            for k in range(first, last):
                block[entries[k] - start] = change[k]
            sums[summed] = _block_sum(block, n)
            summed += 1
            for k in range(first, last):
                block[entries[k] - start] = 0.0
        else:
            half = n // 2 - (n // 2) % _UNROLL
            split = first
            while split < last and entries[split] < start + half:
                split += 1
            # This run again, to add its halves; the right half; the left half, summed first.
            halves_summed[pending] = True
            run_start[pending + 1], run_length[pending + 1] = start + half, n - half
            run_first[pending + 1], run_last[pending + 1] = split, last
            halves_summed[pending + 1] = False
            run_start[pending + 2], run_length[pending + 2] = start, half
            run_first[pending + 2], run_last[pending + 2] = first, split
            halves_summed[pending + 2] = False
            pending += 3
    return sums[0]


@kernel
def _block_sum(block, n):
    """numpy's sum of block[:n], n at most a block."""
    if n < _UNROLL:
        total = 0.0
        for i in range(n):
            total += block[i]
        return total
    s0, s1, s2, s3 = block[0], block[1], block[2], block[3]
    s4, s5, s6, s7 = block[4], block[5], block[6], block[7]
    tail = n - n % _UNROLL
    for i in range(_UNROLL, tail, _UNROLL):
        s0, s1, s2, s3 = s0 + block[i], s1 + block[i + 1], s2 + block[i + 2], s3 + block[i + 3]
        s4, s5, s6, s7 = s4 + block[i + 4], s5 + block[i + 5], s6 + block[i + 6], s7 + block[i + 7]
    total = ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7))
    for i in range(tail, n):
        total += block[i]
    return total
