"""FAM inference (paper eq. 3) of many views at once: the 112 rotated trajectories of one ring
a control step, or a batch of rings. Bit for bit what `perception_reference`
(tests/kernel_references/) computes: each weighted sum adds the fired rules in the same order
as numpy's."""

from __future__ import annotations

from tvl_cli.core.fam_firing_kernel import add_input, fuzzify
from tvl_cli.core.numba_kernel import kernel


@kernel
def infer_views(
    rings, ring_of_view, rotation_of_view, firing, lookup, trajectory_at, strength, offset,
    velocities, experience,
):  # fmt: skip
    """Fill velocities (V, J) m/s and experience (V, J) with what V views perceive.

    View v reads the ring rings[ring_of_view[v]] (16,) metres rotated by k =
    rotation_of_view[v]: ring[(i + k) % 16] is read as S_i. firing: core.fam_firing.Firing's
    kernel_inputs(). lookup (2 cols, R): each rule's velocity (rows 0 .. cols - 1) and
    experience (rows cols .. 2 cols - 1) per column; trajectory_at (T, cols): the trajectory
    each table's column holds, -1 where none. strength and offset (2^n,): room for each
    corner's firing strength and rule offset.
    """
    sonars, interior, gap_start, gap_low, gap_width, strides, first_rows, input_counts = firing
    groups, _, tables = sonars.shape
    count = rings.shape[1]
    columns = lookup.shape[0] // 2
    for v in range(ring_of_view.shape[0]):
        ring = rings[ring_of_view[v]]
        rotation = rotation_of_view[v]
        for t in range(tables):
            rule = first_rows[t]  # the cell's lowest corner
            strength[0], offset[0], size = 1.0, 0, 1
            for i in range(input_counts[t]):
                x = ring[(sonars[0, i, t] + rotation) % count]
                for g in range(1, groups):
                    other = ring[(sonars[g, i, t] + rotation) % count]
                    if other < x:
                        x = other
                lower, upper = fuzzify(x, i * tables + t, interior, gap_start, gap_low, gap_width)
                rule += lower * strides[i, t]
                size = add_input(strength, offset, size, upper, strides[i, t])
            total = 0.0  # of w, summed with the first column's sums (a pass fewer)
            first_column = True
            for col in range(columns):
                j = trajectory_at[t, col]
                if j < 0:
                    continue
                velocity_sum = experience_sum = 0.0  # of w * V, w * E
                for c in range(size):
                    w = strength[c]
                    if w == 0.0:  # adds nothing to any sum
                        continue
                    if first_column:
                        total += w
                    at = rule + offset[c]
                    velocity_sum += w * lookup[col, at]
                    experience_sum += w * lookup[columns + col, at]
                first_column = False
                velocities[v, j] = velocity_sum / total
                experience[v, j] = experience_sum / total
