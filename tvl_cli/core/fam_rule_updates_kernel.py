"""Training's rule updates (paper eq. 1-2) of one table, and how much they changed each
velocity they recomputed: bit for bit what `rule_updates_reference`
(tests/kernel_references/) computes.

Sums are added in numpy's order: each chunk of exemplars corner by corner, exemplar by
exemplar, into sums of its own (as np.bincount did), which are then added to the batch's.
"""

from __future__ import annotations

from tvl_cli.core.fam_firing_kernel import fuzzify
from tvl_cli.core.numba_kernel import inlined, kernel

# Exemplars whose inputs are loaded input by input: enough rows fetched from memory at once
# to hide its latency, few enough to stay in the core's first cache for the next input.
LOAD_BLOCK = 64


@kernel
def train_table(
    readings, velocities_mps, rows, columns, pass_ends, pass_sonars, partitions, strides,
    corner_offsets, high_inputs, chunk_rows, lookup, first_row, table_columns, weighted_sum,
    sums, met, upper, lowest, strength, weighted, change,
):  # fmt: skip
    """Add exemplars to one table; how many entries it recomputed (K), listed in met[0, :K]
    in the order first met, with the absolute change of each one's velocity in change[:K] m/s.

    readings (N * 16,) metres: the rings, row after row; velocities_mps (N,) their labels.
    Pass p trains exemplars rows[pass_ends[p - 1]:pass_ends[p]] into the table's columns
    columns[...] (same slice), reading its n inputs from the sonar groups pass_sonars[p]
    (g, n) (a symmetric pass reads the mirrored ring). partitions: core.fuzzy.StackedPartitions'
    (interior_m, gap_start, gap_low_m, gap_width_m) of the n inputs; strides (n,): each input's
    entry step; corner_offsets (2^n,): each corner's entry from the lowest; high_inputs (h):
    corner strengths are kept for the first h inputs and the other n - h apart. chunk_rows:
    exemplars summed apart before joining the batch's sums. lookup (2 cols, R): velocity rows
    0 .. cols - 1, experience rows cols .. 2 cols - 1, the table's rules from first_row on.
    weighted_sum (E,) = (R_t * traj_t,): the table's sums of w * v, entry = rule * traj_t +
    column, traj_t = table_columns.
    Room to work in: sums (4, E) zeros, left zero (the batch's and a chunk's sums of w and of
    w * v); met (2, E) (the entries the batch and the chunk met); for M = min(chunk_rows,
    rows) exemplars, upper (n, M), lowest (M,), strength (2^h + 2^(n - h), M) and weighted
    (M,) (each one's reading and then upper degree in each input, its lowest
    corner's entry, the strengths of the corners of its first h inputs and then of the rest,
    and its label); change (K,) for K at most min(E, rows * 2^n). Readings are finite or
    +inf, labels finite (core.fam.Fam.train refuses the rest).
    """
    met_count = 0  # the entries the batch has met so far, listed in met[0]
    start = 0
    for p in range(pass_sonars.shape[0]):
        for chunk_start in range(start, pass_ends[p], chunk_rows):
            chunk_end = chunk_start + chunk_rows
            if chunk_end > pass_ends[p]:
                chunk_end = pass_ends[p]
            chunk = rows[chunk_start:chunk_end]
            _load_chunk(readings, velocities_mps, chunk, pass_sonars[p], upper, weighted)
            _fuzzify_chunk(
                chunk.shape[0], columns[chunk_start:chunk_end], partitions, strides, upper, lowest
            )
            _corner_strengths(chunk.shape[0], high_inputs, upper, strength)
            met_count = _sum_chunk(
                chunk.shape[0], corner_offsets, high_inputs, lowest, strength, weighted, sums,
                met, met_count,
            )  # fmt: skip
        start = pass_ends[p]
    _update_rules(met_count, met[0], sums, lookup, first_row, table_columns, weighted_sum, change)
    return met_count


@inlined
def _load_chunk(readings, velocities_mps, chunk, sonars, upper, weighted):
    """Each exemplar's label into weighted (M,) m/s, and its reading of each input, the nearest
    of the input's sonar group sonars (g, n), into upper (n, M) metres."""
    groups, inputs = sonars.shape
    count = readings.shape[0] // velocities_mps.shape[0]
    exemplars = chunk.shape[0]
    # In loops of loads alone: a table's rows lie scattered through rings too large for the
    # cache, and only loads with no fuzzy arithmetic between them are fetched from memory
    # together.
    for m in range(exemplars):
        weighted[m] = velocities_mps[chunk[m]]
    for block in range(0, exemplars, LOAD_BLOCK):
        block_end = block + LOAD_BLOCK
        if block_end > exemplars:
            block_end = exemplars
        for i in range(inputs):
            sonar = sonars[0, i]
            for m in range(block, block_end):
                upper[i, m] = readings[chunk[m] * count + sonar]
            for g in range(1, groups):  # the nearest of the input's sonars
                sonar = sonars[g, i]
                for m in range(block, block_end):
                    x, nearest = readings[chunk[m] * count + sonar], upper[i, m]
                    upper[i, m] = x if x < nearest else nearest


@inlined
def _fuzzify_chunk(exemplars, columns, partitions, strides, upper, lowest):
    """Turn the first `exemplars` readings upper (n, M) metres into their upper degrees, and
    put each exemplar's lowest corner's entry, from its column columns (M,), in lowest (M,)."""
    interior, gap_start, gap_low, gap_width = partitions
    for m in range(exemplars):
        entry = columns[m]
        for i in range(upper.shape[0]):
            lower, upper[i, m] = fuzzify(upper[i, m], i, interior, gap_start, gap_low, gap_width)
            entry += lower * strides[i]
        lowest[m] = entry


@inlined
def _corner_strengths(exemplars, high_inputs, upper, strength):
    """Each exemplar's corner strengths (2^h + 2^(n - h), M) from its upper degrees (n, M)."""
    inputs = upper.shape[0]
    # A corner's strength is the least of its sets' degrees, and the least of two leasts is
    # exact: so each exemplar keeps the corners of its first h inputs (rows 0 .. 2^h - 1) and
    # of the rest (rows 2^h on), and _sum_chunk takes corner c as the lesser of its high
    # part's and its low part's. The full 2^n x M table would outgrow the core's cache for the
    # larger tables.
    for half in range(2):
        row, first_input, last_input = 0, 0, high_inputs
        if half == 1:
            row, first_input, last_input = 1 << high_inputs, high_inputs, inputs
        for m in range(exemplars):
            strength[row, m] = 1.0
        # Input by input, corner c taking the input's lower set as 2c and its upper as
        # 2c + 1, from the top so that each is read before it is written.
        size = 1
        for i in range(first_input, last_input):
            for c in range(size - 1, -1, -1):
                for m in range(exemplars):
                    s, u = strength[row + c, m], upper[i, m]
                    strength[row + 2 * c, m] = s if s < 1.0 - u else 1.0 - u
                    strength[row + 2 * c + 1, m] = s if s < u else u
            size *= 2


@inlined
def _sum_chunk(
    exemplars, corner_offsets, high_inputs, lowest, strength, weighted, sums, met, met_count
):
    """Add a chunk's exemplars to the batch's sums of w and w * v (sums[0], sums[1]) through
    the chunk's own (sums[2], sums[3]); how many entries the batch has met now, listed in
    met[0] (met_count of them before the chunk)."""
    batch_w, batch_wv, chunk_w, chunk_wv = sums[0], sums[1], sums[2], sums[3]
    batch_met, chunk_met = met[0], met[1]
    entries, corners = batch_w.shape[0], corner_offsets.shape[0]
    high_corners, low_corners = 1 << high_inputs, corners >> high_inputs  # 2^h, 2^(n - h)
    # Summed as np.bincount sums: corner by corner, exemplar by exemplar, into the chunk's own
    # sums, then added to the batch's. A chunk of fewer corners than the table has entries
    # lists the entries it meets (skipping corners of strength 0, which add nothing: a reading
    # in a shoulder fires half of them); a bigger one goes through every entry.
    listing = exemplars * corners < entries
    chunk_count = 0
    for c in range(corners):
        offset = corner_offsets[c]
        high, low = c // low_corners, high_corners + c % low_corners
        for m in range(exemplars):
            at, w = lowest[m] + offset, strength[high, m]
            if strength[low, m] < w:
                w = strength[low, m]
            if listing:
                if w == 0.0:
                    continue
                if chunk_w[at] == 0.0:
                    chunk_met[chunk_count] = at
                    chunk_count += 1
            chunk_w[at] += w
            chunk_wv[at] += w * weighted[m]
    for k in range(chunk_count if listing else entries):
        at = chunk_met[k] if listing else k
        if chunk_w[at] == 0.0:
            continue
        if batch_w[at] == 0.0:
            batch_met[met_count] = at
            met_count += 1
        batch_w[at] += chunk_w[at]
        batch_wv[at] += chunk_wv[at]
        chunk_w[at] = chunk_wv[at] = 0.0
    return met_count


@inlined
def _update_rules(
    met_count, batch_met, sums, lookup, first_row, table_columns, weighted_sum, change
):
    """Recompute the velocity and experience of the met_count entries batch_met lists from the
    batch's sums (eq. 1-2), noting each velocity's absolute change (m/s) in change, and leave
    the sums zero."""
    batch_w, batch_wv = sums[0], sums[1]
    lookup_columns = lookup.shape[0] // 2
    for k in range(met_count):
        at = batch_met[k]
        rule, column = first_row + at // table_columns, at % table_columns
        experience = lookup[lookup_columns + column, rule] + batch_w[at]
        weighted_sum[at] += batch_wv[at]
        velocity = weighted_sum[at] / experience
        change[k] = abs(velocity - lookup[column, rule])
        lookup[column, rule] = velocity
        lookup[lookup_columns + column, rule] = experience
        batch_w[at] = batch_wv[at] = 0.0
