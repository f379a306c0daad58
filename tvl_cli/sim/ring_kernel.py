"""The sonar ring's ray casting, for any number of robots in one world at once.

Each ray's fate is decided by the first surface it meets (sim.sonar states the echo rules):
the nearest crossing among the walls of the cells it crosses, the discs and the ring walls;
then its
echo, by the specular rule, a corner or edge near the hit, the wall's roughness, or a
pillar's nearest point. A transducer reads its nearest echo plus noise, clamped to the range.

Agrees with `ring_reference` (tests/kernel_references/) to within 1e-12 m rather than bit
for bit: numpy's matrix products may fuse a multiply and an add (BLAS on FMA hardware), where
this rounds each one.

The arguments come in tuples, each unpacked by name where it is used:
    layout = (transducers, rays)
        transducers (16, 2): each transducer's outward normal in the body frame, S0 ahead, CCW
        rays (16 * r, 4): each ray's body-frame direction (cos, sin), then its offset d from its
            transducer's normal as body_radius_m * (cos d, sin d); beam by beam
    walls = (start, normal, moment, length, ends, corner_sides, roughness)
        as sim.geometry.StaticGeometry's seg_start, seg_normal, seg_moment, seg_len, seg_ends,
        corner_sides and seg_roughness (n,): 0 to 1, how much sound each wall scatters
    grid = (x0_m, y0_m, cell_m, columns, rows, first, walls, lines)
        sim.wall_grid.WallGrid's cells of walls (kernel_input)
    model = (body_radius_m, behind_m, cos_specular, corner_slope, corner_min_radius_m,
             edge_echo_range_m, max_range_m, min_range_m, noise_sigma_m, noise_fraction, ideal)
        behind_m: a crossing this far behind a transducer lies inside the body (touching);
        cos_specular: a smooth surface echoes when met within this cosine of its normal;
        a corner echoes to a ray meeting one of its walls within max(corner_min_radius_m,
        corner_slope * range) of it; the rest as core.robot_config.SonarConfig
"""

from __future__ import annotations

import math

from tvl_cli.core.numba_kernel import inlined, kernel

# A ray's line crosses a wall's line this far beyond the wall's ends (as a fraction of its
# length) at most for the wall to be tested exactly: any wider than rounding could reach.
_BEYOND_ENDS = 1.0 + 1e-9
# Which root of a circle a ray meets: a disc's near one, a ring wall's far one (seen from
# inside). A float, not a flag, so that one compiled function serves both.
_DISC = 1.0
_RING_WALL = -1.0


@kernel
def ring_ranges(
    poses, noise, layout, walls, grid, reach_m, discs, rings, rings_rough, model, readings,
    sources,
):  # fmt: skip
    """Fill readings (N, 16) with the metres read by N robots at poses (N, 3) (x, y metres,
    heading rad), and sources (N, 16) with the obstacle each beam's echo came from, numbered
    walls first, then discs, then ring walls (-1: no echo).

    Each ray tests the walls of the grid's cells it crosses within reach_m of its
    transducer, nearest first, until a cell ends beyond its nearest crossing (of equally
    near crossings, the wall numbered first wins), and every disc (m, 3) and ring wall
    (k, 3) (x, y, r metres; rings_rough (k,) their roughness). noise (N, 16): standard
    normal draws, used unless the model is ideal.
    """
    transducers, rays = layout
    body_radius_m = model[0]
    count = transducers.shape[0]
    per_beam = rays.shape[0] // count
    for robot in range(poses.shape[0]):
        x, y, heading = poses[robot, 0], poses[robot, 1], poses[robot, 2]
        cos_h, sin_h = math.cos(heading), math.sin(heading)
        for beam in range(count):
            ux, uy = transducers[beam, 0], transducers[beam, 1]
            ox = x + body_radius_m * (ux * cos_h - uy * sin_h)  # the transducer O, metres
            oy = y + body_radius_m * (ux * sin_h + uy * cos_h)
            nearest = math.inf  # metres: the beam's nearest echo
            nearest_source = -1
            for ray in range(beam * per_beam, (beam + 1) * per_beam):
                bx, by = rays[ray, 0], rays[ray, 1]
                dx = bx * cos_h - by * sin_h  # the ray's unit direction D
                dy = bx * sin_h + by * cos_h
                # D.O and cross(O, D), the ray leaving the body's edge at its offset
                along = dx * x + dy * y + rays[ray, 2]
                across = dy * x - dx * y + rays[ray, 3]
                echo, source = _ray_echo(
                    ox, oy, dx, dy, along, across, walls, grid, reach_m, discs, rings,
                    rings_rough, model,
                )  # fmt: skip
                if echo < nearest:
                    nearest, nearest_source = echo, source
            readings[robot, beam], sources[robot, beam] = _reading(
                nearest, nearest_source, noise[robot, beam], model
            )


# Inlined, as _nearest_wall is: each is called for every ray with arrays, whose reference
# counts a call of its own takes in and out. As kernels of their own, a reading in the lab
# took 33 µs against 20 µs inlined (benchmarks/sim_speed.py).
@inlined
def _ray_echo(
    ox, oy, dx, dy, along, across, walls, grid, reach_m, discs, rings, rings_rough, model
):  # fmt: skip
    """(echo, source) of one ray from the transducer O in direction D: the echo of the first
    surface it meets (metres, inf for none) and that surface, numbered as ring_ranges
    numbers them."""
    _, normal, moment, length_m, ends, corner_sides, roughness = walls
    behind_m, ideal = model[1], model[10]
    first_disc = length_m.shape[0]
    first_ring = first_disc + discs.shape[0]
    hit, wall, hit_cross, hit_s = _nearest_wall(
        ox, oy, dx, dy, across, normal, moment, grid, -behind_m, reach_m
    )
    echo = hit
    source = wall
    if wall >= 0 and not ideal:
        echo = _wall_echo(
            hit, hit_s, hit_cross, length_m[wall], ends[wall, 0, 0] - ox, ends[wall, 0, 1] - oy,
            ends[wall, 1, 0] - ox, ends[wall, 1, 1] - oy, corner_sides[wall, 0],
            corner_sides[wall, 1], roughness[wall], model,
        )  # fmt: skip
    for j in range(discs.shape[0]):
        disc_hit, disc_echo = _circle(
            dx, dy, along, across, discs[j, 0], discs[j, 1], discs[j, 2], 0.0, _DISC, model
        )
        if disc_hit < hit:
            hit, echo, source = disc_hit, disc_echo, first_disc + j
    for j in range(rings.shape[0]):
        ring_hit, ring_echo = _circle(
            dx, dy, along, across, rings[j, 0], rings[j, 1], rings[j, 2], rings_rough[j],
            _RING_WALL, model,
        )  # fmt: skip
        if ring_hit < hit:
            hit, echo, source = ring_hit, ring_echo, first_ring + j
    return echo, source


# Inlined, so that it compiles with ring_ranges: as a kernel of its own it compiled twice, for
# the literal -1 a beam's source starts at and for any source.
@inlined
def _reading(nearest, source, noise, model):
    """(reading, source) of a transducer whose nearest echo is `nearest` metres (inf: none)
    from `source`: plus its noise (a standard normal draw) unless the model is ideal,
    clamped to the range; the maximum range and -1 where nothing echoed within it."""
    max_range_m, min_range_m, noise_sigma_m, noise_fraction, ideal = model[6:]
    if not nearest <= max_range_m:
        return max_range_m, -1
    if not ideal:
        sigma = noise_sigma_m + noise_fraction * nearest
        nearest = nearest + sigma * noise
    reading = nearest if nearest > min_range_m else min_range_m
    return (reading if reading < max_range_m else max_range_m), source


@inlined
def _nearest_wall(ox, oy, dx, dy, across, normal, moment, grid, t_low, t_high):
    """(t, wall, cross(D, E), s) of the nearest crossing of the ray O + tD, t_low < t, with a
    wall, walking the grid's cells along it as far as t_high; (inf, -1, 0, 0) for none."""
    x0, y0, cell_m, columns, rows, first, cell_walls, lines = grid
    hit = math.inf
    wall = -1
    hit_cross = hit_s = 0.0
    t_in, t_out = _span_in_box(ox, oy, dx, dy, t_low, t_high, x0, y0, columns * cell_m,
                               rows * cell_m)  # fmt: skip
    if not t_in <= t_out:
        return hit, wall, hit_cross, hit_s
    column = _cell_of(ox + t_in * dx - x0, cell_m, columns)
    row = _cell_of(oy + t_in * dy - y0, cell_m, rows)
    while True:
        cell = row * columns + column
        first_entry, last_entry = first[cell], first[cell + 1]
        # Ray O + tD meets segment A + sE where t = cross(A - O, E) / cross(D, E) and
        # s = cross(A - O, D) / cross(D, E). Most walls lie off the ray's line: leave them
        # before dividing, with room to spare so that the exact tests below decide every
        # wall they could pass. One pass over the cell's walls: screening them all into
        # scratch first and then testing those left cost a reading in the lab 20 µs against 16
        # (benchmarks/sim_speed.py).
        for e in range(first_entry, last_entry):
            cross = dx * lines[0, e] + dy * lines[1, e]
            s_num = (dy * lines[2, e] - dx * lines[3, e]) - across
            if not abs(s_num) <= abs(cross) * _BEYOND_ENDS:
                continue
            w = cell_walls[e]
            s = s_num / cross
            t = (moment[w] - (ox * normal[0, w] + oy * normal[1, w])) / cross
            # (nan fails every test: the ray runs along the wall's line)
            if s >= 0.0 and s <= 1.0 and t > t_low and (t < hit or (t == hit and w < wall)):
                hit, wall, hit_cross, hit_s = t, w, cross, s
        # Where the ray leaves this cell: any crossing beyond lies in the cells ahead.
        t_column = _t_to_edge(ox - x0, dx, column, cell_m)
        t_row = _t_to_edge(oy - y0, dy, row, cell_m)
        t_exit = t_column if t_column < t_row else t_row
        if hit <= t_exit or t_exit >= t_out:
            return hit, wall, hit_cross, hit_s
        if t_column < t_row:
            column += 1 if dx > 0.0 else -1
        else:
            row += 1 if dy > 0.0 else -1
        if column < 0 or column >= columns or row < 0 or row >= rows:
            return hit, wall, hit_cross, hit_s


@kernel
def _span_in_box(ox, oy, dx, dy, t_low, t_high, x0, y0, width, height):
    """The part [t_in, t_out] of O + tD, t_low <= t <= t_high, inside the box from (x0, y0)
    of this width and height (t_in > t_out: none)."""
    for o, d, low, size in ((ox, dx, x0, width), (oy, dy, y0, height)):
        if d == 0.0:
            if o < low or o > low + size:
                return 1.0, 0.0
        else:
            near = (low - o) / d
            far = (low + size - o) / d
            if near > far:
                near, far = far, near
            if near > t_low:
                t_low = near
            if far < t_high:
                t_high = far
    return t_low, t_high


@kernel
def _cell_of(offset_m, cell_m, cells):
    """The cell holding a point this far along an axis from the grid's edge, clamped to the
    grid (a point on its edge, or a hair past it by rounding)."""
    index = math.floor(offset_m / cell_m)
    if index < 0:
        return 0
    return cells - 1 if index > cells - 1 else index


@kernel
def _t_to_edge(offset_m, d, index, cell_m):
    """Where the ray, leaving from this far along an axis from the grid's edge in direction
    d, reaches the far edge (along d) of cell `index` on that axis; inf if it runs along it."""
    if d > 0.0:
        return ((index + 1) * cell_m - offset_m) / d
    if d < 0.0:
        return (index * cell_m - offset_m) / d
    return math.inf


@kernel
def _wall_echo(
    hit, s, cross, length, to_start_x, to_start_y, to_end_x, to_end_y, start_side, end_side,
    roughness, model,
):  # fmt: skip
    """The echo (metres, inf for none) of a ray meeting a wall `hit` metres away, a fraction s
    along it, with cross(D, E) = cross; the wall's ends lie at to_start and to_end from the
    transducer, and the walls meeting them leave on start_side and end_side."""
    (_, _, cos_specular, corner_slope, corner_min_radius_m, edge_echo_range_m, max_range_m,
     _, _, _, _) = model  # fmt: skip
    # |cross(D, E)| / |E| is the cosine of incidence.
    cos_incidence = abs(cross) / length
    if cos_incidence >= cos_specular or hit <= 0.0:
        return hit
    # For a forward hit the transducer is on the side of the wall given by the sign of
    # cross(D, E); a corner is concave when the other wall leaves it on that same side, and
    # an edge when it leaves on the other side or no wall meets it there.
    reach = corner_slope * hit
    if reach < corner_min_radius_m:
        reach = corner_min_radius_m
    echo = math.inf
    if abs(s - 0.0) * length <= reach:
        corner_m = math.hypot(to_start_x, to_start_y)
        if (start_side * cross > 0.0 or corner_m <= edge_echo_range_m) and corner_m < echo:
            echo = corner_m
    if abs(s - 1.0) * length <= reach:
        corner_m = math.hypot(to_end_x, to_end_y)
        if (end_side * cross > 0.0 or corner_m <= edge_echo_range_m) and corner_m < echo:
            echo = corner_m
    diffuse = roughness > 0.0 and hit <= max_range_m * math.sqrt(roughness * cos_incidence)
    if diffuse and hit < echo:
        echo = hit
    return echo


@kernel
def _circle(dx, dy, along, across, cx, cy, radius, roughness, side, model):
    """(hit, echo) metres of the ray against a disc (side _DISC) or a ring wall seen from
    inside (side _RING_WALL), centred at (cx, cy)."""
    _, behind_m, cos_specular, _, _, _, max_range_m, _, _, _, ideal = model
    # |O + tD - C| = r at t = b -/+ h: b = D.(C - O) is where the ray passes nearest the
    # centre, at a distance q = cross(C - O, D), and h = sqrt(r^2 - q^2). A disc is met at
    # the near root, a ring at the far one; at the hit point the cosine between the ray and
    # the normal is h / r.
    b = (dx * cx + dy * cy) - along
    q = (dy * cx - dx * cy) - across
    square = radius * radius - q * q
    if not square >= 0.0:  # the ray's line misses the circle
        return math.inf, math.inf
    root = math.sqrt(square)
    t = b - side * root
    if not t > -behind_m:
        return math.inf, math.inf
    if ideal:
        return t, t
    if side == _DISC:
        # A round pillar always turns part of its surface square to the transducer: when any
        # ray of the cone meets it, the echo returns from that nearest point of it.
        return t, math.hypot(b, q) - radius
    cos_incidence = root / radius
    heard = cos_incidence >= cos_specular or t <= 0.0
    if roughness > 0.0:
        heard = heard or t <= max_range_m * math.sqrt(roughness * cos_incidence)
    return t, (t if heard else math.inf)
