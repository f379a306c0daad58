"""Fuzzy associative memory: sonar ring -> trajectory velocities (paper §3 and §4).

Each table of a FamConfig is an N-dimensional matrix of rules, one axis per input and one
rule per combination of fuzzy sets; a rule's flat index is the C-order ravel over the
table's shape. Each rule holds, for every trajectory of its table, the experience
E = sum of w (eq. 1) and the weighted sum S = sum of w * v, so its velocity is V = S / E
(eq. 2); a rule never trained keeps the initial velocity. A reading fires the 2^n rules at
the corners of its cell with strength w = min of their memberships (min AND), and the
perceived velocity is the w-weighted average of their V (eq. 3).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from tvl_cli.core.config import (
    SONAR_COUNT,
    FamConfig,
    FamTable,
    Partition,
    mirror_sonar,
    mirror_trajectory,
)
from tvl_cli.core.errors import BadInput
from tvl_cli.core.explain import Explanation, FiredRule, reading
from tvl_cli.core.fam_configs import validate_fam_config
from tvl_cli.core.fuzzy import StackedPartitions

DEFAULT_INIT_VELOCITY_MPS = 0.1  # paper §3.1: an unknown reading must be perceived as slow
# Work per chunk, big enough that per-call costs vanish and small enough to bound memory:
# corners (exemplars x 2^n) fired at once in training, and entries (rings x corners x
# stored columns) gathered at once in inference.
TRAIN_CHUNK_CORNERS = 2**18
INFER_CHUNK_ENTRIES = 2**19

# An input that always sits fully in its upper set, with stride 0: padding a table with it
# leaves its rules and strengths unchanged (the lower corners get strength 0), so tables with
# fewer inputs can be fired in one array with the widest.
_PADDING = Partition(("pad-lower", "pad-upper"), (-2.0, -1.0))


def rule_set_indices(table: FamTable, rules: np.ndarray | None = None) -> np.ndarray:
    """The fuzzy-set index of each input (R, n) for flat rule indices (R,) (default: all)."""
    if rules is None:
        rules = np.arange(table.rule_count)
    return np.stack(np.unravel_index(np.asarray(rules), table.shape), axis=-1)


def _strides(shape: tuple[int, ...]) -> np.ndarray:
    """Flat-index step of each axis of a C-order array of this shape."""
    return np.array([int(np.prod(shape[k + 1 :])) for k in range(len(shape))], dtype=np.intp)


@dataclass(frozen=True, slots=True, eq=False)
class _Firing:
    """Fires T tables side by side, padded to the same number n of inputs, so C = 2^n corners.

    Arrays end with the tables and the exemplars (T, N), so that every step works on whole
    contiguous rows of them.
    """

    sonars: np.ndarray  # (g, n, T, 1) ring indices; an input is the minimum over its g readings
    partitions: StackedPartitions  # the n * T partitions, input by input
    strides: np.ndarray  # (n, T, 1) index step of each input's set, times the row scale
    corners: np.ndarray  # (C, T, 1) index offset of each corner from the lowest, plus first row

    @classmethod
    def of(
        cls, tables: Sequence[FamTable], first_rows: Sequence[int], inputs: int, scale: int = 1
    ) -> _Firing:
        groups = max(len(i.sonars) for t in tables for i in t.inputs)
        sonars = np.zeros((groups, inputs, len(tables)), dtype=np.intp)
        strides = np.zeros((inputs, len(tables)), dtype=np.intp)
        partitions = []
        for k in range(inputs):
            for t, table in enumerate(tables):
                if k < len(table.inputs):
                    group = table.inputs[k].sonars
                    # Repeating a sonar pads the group without changing its minimum.
                    sonars[:, k, t] = group + (group[0],) * (groups - len(group))
                    strides[k, t] = _strides(table.shape)[k] * scale
                    partitions.append(table.inputs[k].partition)
                else:
                    partitions.append(_PADDING)
        # Corner c takes the upper set of input k when bit (n - 1 - k) of c is set, the order
        # in which fire() builds its strengths.
        bits = (np.arange(2**inputs)[:, None] >> np.arange(inputs - 1, -1, -1)) & 1  # (C, n)
        corners = bits @ strides + np.asarray(first_rows, dtype=np.intp) * scale  # (C, T)
        return cls(
            sonars[..., None],
            StackedPartitions.of(partitions),
            strides[..., None],
            corners[..., None],
        )

    def mirrored(self) -> _Firing:
        """The same firing of the mirror image of the ring (Si <-> S(16-i))."""
        sonars = np.vectorize(mirror_sonar, otypes=[np.intp])(self.sonars)
        return _Firing(sonars, self.partitions, self.strides, self.corners)

    def fire(self, x: np.ndarray, scratch: _Scratch | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Lowest corner index (T, N) and corner strengths (C, T, N) of inputs x (n, T, N) m.

        Corner c's index is the lowest index plus corners[c]. The strengths are written into
        `scratch` when given.
        """
        inputs, tables, count = x.shape
        lower, upper = self.partitions.fuzzify(x.reshape(inputs * tables, count))
        lower = lower.reshape(x.shape)
        upper = upper.reshape(x.shape)
        base = (lower * self.strides).sum(axis=0)
        degree = np.empty((inputs, 2, tables, count))  # (n, 2, T, N): lower set's, upper set's
        np.subtract(1.0, upper, out=degree[:, 0])
        degree[:, 1] = upper
        strength = degree[0]
        for k in range(1, inputs):
            out = (
                None if scratch is None else scratch.strengths[k - 1].reshape(-1, 2, tables, count)
            )
            strength = np.minimum(strength[:, None], degree[k], out=out).reshape(-1, tables, count)
        return base, strength


class _Scratch:
    """Temporaries for inferring a fixed number of rings, kept from call to call.

    Perception runs every control step, and allocating arrays this size afresh each time
    costs more in page faults than the arithmetic.
    """

    def __init__(self, firing: _Firing, stored_rows: int, count: int) -> None:
        corners, tables = firing.corners.shape[:2]
        inputs = firing.strides.shape[0]
        # item k - 1: the (2^(k+1), T, N) corner strengths after combining inputs 0..k
        self.strengths = [np.empty((2 ** (k + 1), tables, count)) for k in range(1, inputs)]
        self.rules = np.empty((corners, tables, count), dtype=np.intp)  # (C, T, N) lookup columns
        self.stored = np.empty((stored_rows, corners, tables, count))  # (2 cols, C, T, N)


class Fam:
    """The tables of a FamConfig with their learnt velocities and experience.

    perceive() reuses buffers of its own, so a Fam serves one thread at a time.
    """

    def __init__(
        self,
        config: FamConfig,
        trajectory_names: Sequence[str],
        init_velocity_mps: float = DEFAULT_INIT_VELOCITY_MPS,
    ) -> None:
        """Untrained: every entry at `init_velocity_mps` with no experience.

        `trajectory_names` runs left to right, so trajectory j mirrors len - 1 - j.
        """
        validate_fam_config(config, trajectory_names)
        if not (math.isfinite(init_velocity_mps) and init_velocity_mps >= 0):
            raise BadInput(f"initial velocity must be >= 0 m/s (got {init_velocity_mps})")
        self._config = config
        self._names = tuple(trajectory_names)
        self._init = float(init_velocity_mps)
        tables = config.tables
        self._columns = max(len(t.trajectories) for t in tables)
        self._first_rows = np.cumsum([0] + [t.rule_count for t in tables])
        # Columns are the rules of all tables, one table after another. Rows 0..cols-1 hold
        # the velocities (m/s) of each table's trajectories, rows cols..2 cols-1 their experience.
        self._lookup = np.zeros((2 * self._columns, self._first_rows[-1]))  # (2 cols, R)
        self._lookup[: self._columns] = self._init
        self._weighted_sum = [np.zeros((t.rule_count, len(t.trajectories))) for t in tables]
        # each (R_t, traj_t): sum of w * v in m/s

        widest = max(len(t.inputs) for t in tables)
        self._firing = _Firing.of(tables, self._first_rows[:-1].tolist(), widest)
        # (g, n, T, 16): rotation k reads ring[(i + k) % 16] where it would read ring[i]
        self._rotated_sonars = (self._firing.sonars + np.arange(SONAR_COUNT)) % SONAR_COUNT
        # Training fires one table at a time, unpadded, straight into (rule, column) entries.
        self._train_firings = [
            _Firing.of((t,), (0,), len(t.inputs), scale=len(t.trajectories)) for t in tables
        ]
        self._mirror_firings = [f.mirrored() for f in self._train_firings]
        self._perceive_scratch = _Scratch(self._firing, len(self._lookup), SONAR_COUNT)

        where = {
            n: (t, table.trajectories.index(n))
            for t, table in enumerate(tables)
            for n in table.trajectories
        }
        self._table_of = np.array([where[n][0] for n in self._names], dtype=np.intp)
        self._column_of = np.array([where[n][1] for n in self._names], dtype=np.intp)
        # Where trajectory j's averages land in the (2 cols * T, N) inference result.
        self._velocity_at = self._column_of * len(tables) + self._table_of
        self._experience_at = self._velocity_at + self._columns * len(tables)

    @classmethod
    def from_tables(
        cls,
        config: FamConfig,
        trajectory_names: Sequence[str],
        velocities_mps: Sequence[np.ndarray],
        experience: Sequence[np.ndarray],
        init_velocity_mps: float = DEFAULT_INIT_VELOCITY_MPS,
    ) -> Fam:
        """Rebuild a FAM from each table's (R_t, traj_t) velocities and experience.

        The velocities are kept bit for bit; the weighted sums become velocity x experience.
        """
        fam = cls(config, trajectory_names, init_velocity_mps)
        if len(velocities_mps) != len(config.tables) or len(experience) != len(config.tables):
            raise BadInput(
                f"{len(config.tables)} tables in the configuration but {len(velocities_mps)} "
                f"velocity and {len(experience)} experience arrays"
            )
        for t, table in enumerate(config.tables):
            shape = (table.rule_count, len(table.trajectories))
            v = np.asarray(velocities_mps[t], dtype=np.float64)
            e = np.asarray(experience[t], dtype=np.float64)
            if v.shape != shape or e.shape != shape:
                raise BadInput(
                    f"table {table.name!r}: velocity {v.shape} and experience {e.shape} "
                    f"arrays, expected {shape}"
                )
            if not (np.isfinite(v).all() and np.isfinite(e).all() and (e >= 0).all()):
                raise BadInput(
                    f"table {table.name!r}: velocities and experience must be finite, "
                    "experience >= 0"
                )
            fam._velocity_view(t)[...] = v
            fam._experience_view(t)[...] = e
            fam._weighted_sum[t][...] = v * e
        return fam

    @property
    def config(self) -> FamConfig:
        return self._config

    @property
    def trajectory_names(self) -> tuple[str, ...]:
        return self._names

    @property
    def init_velocity_mps(self) -> float:
        return self._init

    def _velocity_view(self, t: int) -> np.ndarray:
        """Table t's velocities (R_t, traj_t), a view into the lookup."""
        rules = slice(self._first_rows[t], self._first_rows[t + 1])
        return self._lookup[: len(self._config.tables[t].trajectories), rules].T

    def _experience_view(self, t: int) -> np.ndarray:
        """Table t's experience (R_t, traj_t), a view into the lookup."""
        rules = slice(self._first_rows[t], self._first_rows[t + 1])
        first = self._columns
        return self._lookup[first : first + len(self._config.tables[t].trajectories), rules].T

    def velocity_table(self, t: int) -> np.ndarray:
        """A copy of table t's velocities (R_t, traj_t) m/s, columns as table.trajectories."""
        return self._velocity_view(t).copy()

    def experience_table(self, t: int) -> np.ndarray:
        """A copy of table t's experience (R_t, traj_t), columns as table.trajectories."""
        return self._experience_view(t).copy()

    def train(
        self,
        rings: np.ndarray,
        trajectories: np.ndarray,
        velocities_mps: np.ndarray,
        symmetric: bool = True,
    ) -> None:
        """Add exemplars (eq. 1-2): rings (N, 16) m, trajectory indices (N,), labels (N,) m/s.

        With `symmetric`, each exemplar also trains the mirror trajectory on the mirrored
        ring (paper §4.4). The sums are accumulated in a fixed order, so the same exemplars
        in the same batches always give the same bits.
        """
        rings = np.asarray(rings, dtype=np.float64)
        trajectories = np.asarray(trajectories)
        velocities_mps = np.asarray(velocities_mps, dtype=np.float64)
        count = len(rings)
        if rings.shape != (count, SONAR_COUNT):
            raise ValueError(f"rings must be (N, {SONAR_COUNT}), got {rings.shape}")
        if trajectories.shape != (count,) or velocities_mps.shape != (count,):
            raise ValueError("need one trajectory and one velocity per ring")
        if count == 0:
            return
        if trajectories.min() < 0 or trajectories.max() >= len(self._names):
            raise ValueError(f"trajectory indices must be in 0..{len(self._names) - 1}")
        trajectories = trajectories.astype(np.intp)
        mirrors = mirror_trajectory(trajectories, len(self._names))
        for t in range(len(self._config.tables)):
            passes = [(self._train_firings[t], trajectories)]
            if symmetric:
                passes.append((self._mirror_firings[t], mirrors))
            self._train_table(t, rings.ravel(), velocities_mps, passes)

    def _train_table(
        self,
        t: int,
        readings: np.ndarray,
        velocities_mps: np.ndarray,
        passes: list[tuple[_Firing, np.ndarray]],
    ) -> None:
        weighted_sum = self._weighted_sum[t]
        d_experience = np.zeros(weighted_sum.size)  # (R_t * traj_t,) this batch's sum of w
        d_weighted = np.zeros(weighted_sum.size)  # (R_t * traj_t,) its sum of w * v, m/s
        for firing, trajectories in passes:
            mine = np.flatnonzero(self._table_of[trajectories] == t)
            chunk = max(1, TRAIN_CHUNK_CORNERS // len(firing.corners))
            for start in range(0, len(mine), chunk):
                rows = mine[start : start + chunk]
                # (n, 1, M) inputs, gathered straight from the row-major (N * 16,) readings
                x = readings.take(rows * SONAR_COUNT + firing.sonars).min(axis=0)
                base, strength = firing.fire(x)
                base += self._column_of[trajectories[rows]]
                index = (base + firing.corners).ravel()  # (C * M,) (rule, column) entries
                d_experience += np.bincount(index, strength.ravel(), len(d_experience))
                strength *= velocities_mps[rows]
                d_weighted += np.bincount(index, strength.ravel(), len(d_weighted))
        touched = (d_experience > 0).reshape(weighted_sum.shape)
        experience = self._experience_view(t)
        experience += d_experience.reshape(weighted_sum.shape)
        weighted_sum += d_weighted.reshape(weighted_sum.shape)
        # Only touched entries are recomputed: the others keep their exact stored values.
        self._velocity_view(t)[touched] = weighted_sum[touched] / experience[touched]

    def _infer(
        self, x: np.ndarray, scratch: _Scratch | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Velocities (N, J) m/s and experience (N, J) of inputs x (n, T, N) (eq. 3)."""
        base, strength = self._firing.fire(x, scratch)
        if scratch is None:
            stored = self._lookup.take(base + self._firing.corners, axis=1)  # (2 cols, C, T, N)
        else:
            rules = np.add(base, self._firing.corners, out=scratch.rules)
            # mode="clip" lets take write straight into `out` (the rules are in range anyway)
            stored = np.take(self._lookup, rules, axis=1, out=scratch.stored, mode="clip")
        average = np.einsum("mctn,ctn->mtn", stored, strength)  # (2 cols, T, N)
        average /= strength.sum(axis=0)
        flat = average.reshape(-1, x.shape[-1])  # (2 cols * T, N)
        return flat.take(self._velocity_at, axis=0).T, flat.take(self._experience_at, axis=0).T

    def _inputs(self, rings: np.ndarray, rotation: int) -> np.ndarray:
        """Inputs (n, T, N) metres of rings (N, 16) metres under a rotation."""
        sonars = (self._firing.sonars + int(rotation)) % SONAR_COUNT
        return rings.take(np.arange(len(rings)) * SONAR_COUNT + sonars).min(axis=0)

    def _batch(self, rings: np.ndarray, rotation: int) -> tuple[np.ndarray, np.ndarray]:
        rings = np.asarray(rings, dtype=np.float64)
        if rings.shape[-1:] != (SONAR_COUNT,) or rings.ndim > 2:
            raise ValueError(f"rings must be (16,) or (N, 16), got {rings.shape}")
        batch = rings.reshape(-1, SONAR_COUNT)
        chunk = max(1, INFER_CHUNK_ENTRIES // (self._lookup.shape[0] * self._firing.corners.size))
        parts = [
            self._infer(self._inputs(batch[start : start + chunk], rotation))
            for start in range(0, len(batch), chunk)
        ]
        if not parts:
            empty = np.empty((0, len(self._names)))
            return empty, empty.copy()
        velocity = np.concatenate([p[0] for p in parts]) if len(parts) > 1 else parts[0][0]
        experience = np.concatenate([p[1] for p in parts]) if len(parts) > 1 else parts[0][1]
        if rings.ndim == 1:
            return velocity[0], experience[0]
        return velocity, experience

    def velocities(self, rings: np.ndarray, rotation: int = 0) -> np.ndarray:
        """Perceived velocities (J,) m/s of a ring (16,), or (N, J) of rings (N, 16) metres.

        Rotation k perceives as if the robot faced sonar k: ring[(i + k) % 16] is read as S_i.
        """
        return self._batch(rings, rotation)[0]

    def experience(self, rings: np.ndarray, rotation: int = 0) -> np.ndarray:
        """Experience (J,) or (N, J) behind each perceived velocity: the same weighted average."""
        return self._batch(rings, rotation)[1]

    def perceive(self, ring: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Velocities (16, J) m/s and experience (16, J) of one ring (16,) under all rotations.

        Row k is rotation k (paper §4.5): 16 x 7 = 112 trajectories from one reading.
        """
        ring = np.asarray(ring, dtype=np.float64)
        if ring.shape != (SONAR_COUNT,):
            raise ValueError(f"ring must be ({SONAR_COUNT},), got {ring.shape}")
        return self._infer(ring.take(self._rotated_sonars).min(axis=0), self._perceive_scratch)

    def explain(self, ring: np.ndarray) -> Explanation:
        """The memberships, fired rules and weighted averages behind velocities(ring)."""
        ring = np.asarray(ring, dtype=np.float64)
        if ring.shape != (SONAR_COUNT,):
            raise ValueError(f"ring must be ({SONAR_COUNT},), got {ring.shape}")
        x = self._inputs(ring[None], 0)  # (n, T, 1) metres
        base, strength = self._firing.fire(x)
        velocity, experience = self._infer(x)
        tables = self._config.tables
        return Explanation(
            tuple(
                reading(table, fam_input, float(x[k, t, 0]))
                for t, table in enumerate(tables)
                for k, fam_input in enumerate(table.inputs)
            ),
            tuple(
                rule
                for t in range(len(tables))
                for rule in self._fired_rules(t, int(base[t, 0]), strength[:, t, 0])
            ),
            self._names,
            tuple(velocity[0].tolist()),
            tuple(experience[0].tolist()),
        )

    def _fired_rules(self, t: int, base: int, strength: np.ndarray) -> list[FiredRule]:
        """Table t's rules among the corners from `base` with strengths (C,) above 0."""
        table = self._config.tables[t]
        live = np.flatnonzero(strength > 0)
        rules = base + self._firing.corners[live, t, 0] - self._first_rows[t]
        velocity, experience = self._velocity_view(t), self._experience_view(t)
        return [
            FiredRule(
                table.name,
                int(rule),
                tuple(sets.tolist()),
                tuple(i.partition.names[s] for i, s in zip(table.inputs, sets, strict=True)),
                float(strength[corner]),
                table.trajectories,
                tuple(velocity[rule].tolist()),
                tuple(experience[rule].tolist()),
            )
            for rule, sets, corner in zip(rules, rule_set_indices(table, rules), live, strict=True)
        ]
