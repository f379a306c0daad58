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
from collections.abc import Callable, Sequence

import numpy as np

from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import DEFAULT_INIT_VELOCITY_MPS, FamConfig, FamTable
from tvl_cli.core.fam_config_json import validate_fam_config
from tvl_cli.core.fam_firing import Firing, TableTraining
from tvl_cli.core.fired_rules import Explanation, FiredRule, reading
from tvl_cli.core.robot_config import SONAR_COUNT, mirror_trajectory


def rule_set_indices(table: FamTable, rules: np.ndarray | None = None) -> np.ndarray:
    """The fuzzy-set index of each input (R, n) for flat rule indices (R,) (default: all)."""
    if rules is None:
        rules = np.arange(table.rule_count)
    return np.stack(np.unravel_index(np.asarray(rules), table.shape), axis=-1)


class Fam:
    """The tables of a FamConfig with their learnt velocities and experience.

    Training and perception work in buffers of its own, so a Fam serves one thread at a time.
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
        self._firing = Firing.of(tables, self._first_rows[:-1].tolist(), widest)
        self._firing_arrays = self._firing.kernel_inputs()
        # Training fires one table at a time, unpadded, straight into (rule, column) entries.
        self._training = [TableTraining.of(t) for t in tables]

        where = {
            n: (t, table.trajectories.index(n))
            for t, table in enumerate(tables)
            for n in table.trajectories
        }
        self._table_of = np.array([where[n][0] for n in self._names], dtype=np.intp)
        self._column_of = np.array([where[n][1] for n in self._names], dtype=np.intp)
        # (T, cols): the trajectory each table's column holds, -1 where none
        self._trajectory_at = np.full((len(tables), self._columns), -1, dtype=np.intp)
        self._trajectory_at[self._table_of, self._column_of] = np.arange(len(self._names))
        # Where each table's velocity entries start among all of them, table after table.
        self._first_entry = np.cumsum([0] + [w.size for w in self._weighted_sum])
        # (entries,) m/s: how much training changed each velocity entry, zero between batches
        self._change = np.zeros(self._first_entry[-1])
        # Room for each corner's firing strength and rule offset, for the widest table.
        self._corner_strength = np.empty(len(self._firing.corners))  # (C,)
        self._corner_offset = np.empty(len(self._firing.corners), dtype=np.intp)  # (C,)
        # Perception's 16 views of one ring: rotation k faces sonar k.
        self._all_rotations = np.arange(SONAR_COUNT)  # (16,)
        self._one_ring = np.zeros(SONAR_COUNT, dtype=np.intp)  # (16,) every view reads ring 0
        # Compiled kernels, loaded here rather than on import so that no `--help` loads them.
        from tvl_cli.core.fam_perception_kernel import infer_views
        from tvl_cli.core.fam_rule_updates_kernel import train_table

        self._infer_views: Callable[..., None] = infer_views
        self._train_table: Callable[..., int] = train_table

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
    ) -> float:
        """Add exemplars (eq. 1-2): rings (N, 16) m, trajectory indices (N,), labels (N,) m/s.

        With `symmetric`, each exemplar also trains the mirror trajectory on the mirrored
        ring (paper §4.4). The sums are accumulated in a fixed order, so the same exemplars
        in the same batches always give the same bits. Returns the summed absolute change of
        the velocity entries (m/s), added in the order numpy's sum adds all of them.
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
            return 0.0
        if trajectories.min() < 0 or trajectories.max() >= len(self._names):
            raise ValueError(f"trajectory indices must be in 0..{len(self._names) - 1}")
        # A NaN reading has no fuzzy degree, and a label that is not a number no average.
        # (Reductions find them without an array as large as the rings: a minimum is NaN
        # where any reading is, and a sum of speeds finite only where every one is.)
        if np.isnan(rings.min()) or not np.isfinite(velocities_mps.sum()):
            raise ValueError("rings must be numbers (finite or inf) and labels finite")
        trajectories = trajectories.astype(np.intp)
        passes = [trajectories]
        if symmetric:
            passes.append(mirror_trajectory(trajectories, len(self._names)))
        readings = rings.ravel()
        rows_by_pass = [self._rows_by_table(trajectories) for trajectories in passes]
        touched = []
        for t in range(len(self._config.tables)):
            rows = [rows_by_table[t] for rows_by_table in rows_by_pass]
            entries, change = self._train_one_table(t, readings, velocities_mps, passes, rows)
            entries += self._first_entry[t]
            self._change[entries] = change
            touched.append(entries)
        # Every entry summed, as numpy summed the change of a copy of them all (its pairwise
        # order decides the rounding): a reduction of memory kept for it, not two copies.
        summed = float(np.add.reduce(self._change))
        for entries in touched:
            self._change[entries] = 0.0
        return summed

    @property
    def entry_count(self) -> int:
        """How many velocity entries the FAM holds: rules x trajectories, table by table."""
        return int(self._first_entry[-1])

    def _rows_by_table(self, trajectories: np.ndarray) -> list[np.ndarray]:
        """For each table, the rows (ascending) of the exemplars whose trajectories (N,) it
        holds: one stable sort by table for all of them."""
        tables = self._table_of[trajectories].astype(np.uint16)  # a radix sort's keys
        order = np.argsort(tables, kind="stable")
        ends = np.cumsum(np.bincount(tables, minlength=len(self._config.tables)))
        return np.split(order, ends[:-1])

    def _train_one_table(
        self,
        t: int,
        readings: np.ndarray,
        velocities_mps: np.ndarray,
        passes: list[np.ndarray],
        rows: list[np.ndarray],
    ) -> tuple[np.ndarray, np.ndarray]:
        """Train table t on each pass's exemplars rows[p] (by their trajectories (N,), the
        second pass on the mirrored ring); the entries recomputed (K,) and their absolute
        change (K,)."""
        training = self._training[t]
        every_row = np.concatenate(rows)
        exemplars = min(training.chunk_rows, len(every_row))
        corners = len(training.corner_offsets)
        high, low = training.high_inputs, len(training.strides) - training.high_inputs
        change = np.empty(min(self._weighted_sum[t].size, len(every_row) * corners))  # m/s
        recomputed = self._train_table(
            readings,
            velocities_mps,
            every_row,
            np.concatenate([self._column_of[j[r]] for j, r in zip(passes, rows, strict=True)]),
            np.cumsum([len(r) for r in rows]),
            training.pass_sonars[: len(passes)],
            training.partitions,
            training.strides,
            training.corner_offsets,
            training.high_inputs,
            training.chunk_rows,
            self._lookup,
            self._first_rows[t],
            len(self._config.tables[t].trajectories),
            self._weighted_sum[t].reshape(-1),
            training.sums,
            training.met,
            np.empty((len(training.strides), exemplars)),  # (n, M) readings, upper degrees
            np.empty(exemplars, dtype=np.intp),  # (M,) each one's lowest corner's entry
            # (2^h + 2^(n - h), M): the strengths of the corners of each one's halves
            np.empty(((1 << high) + (1 << low), exemplars)),
            np.empty(exemplars),  # (M,) m/s each one's label
            change,
        )
        return training.met[0, :recomputed].copy(), change[:recomputed]

    def _inputs(self, rings: np.ndarray, rotation: int) -> np.ndarray:
        """Inputs (n, T, N) metres of rings (N, 16) metres under a rotation."""
        sonars = (self._firing.sonars[..., None] + int(rotation)) % SONAR_COUNT
        return rings.take(np.arange(len(rings)) * SONAR_COUNT + sonars).min(axis=0)

    def inference_inputs(
        self, rings: np.ndarray, ring_of_view: np.ndarray, rotation_of_view: np.ndarray
    ) -> tuple[object, ...]:
        """The arguments of core.fam_perception_kernel.infer_views for V views, view v reading
        ring rings[ring_of_view[v]] (N, 16) metres under rotation rotation_of_view[v], but
        the (V, J) velocities and experience it fills."""
        return (
            rings, ring_of_view, rotation_of_view, self._firing_arrays, self._lookup,
            self._trajectory_at, self._corner_strength, self._corner_offset,
        )  # fmt: skip

    def _infer(
        self, rings: np.ndarray, ring_of_view: np.ndarray, rotation_of_view: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Velocities (V, J) m/s and experience (V, J) perceived by V views (inference_inputs)."""
        views = (len(ring_of_view), len(self._names))
        velocities, experience = np.empty(views), np.empty(views)  # (V, J) m/s, (V, J)
        self._infer_views(
            *self.inference_inputs(rings, ring_of_view, rotation_of_view), velocities, experience
        )
        return velocities, experience

    def _batch(self, rings: np.ndarray, rotation: int) -> tuple[np.ndarray, np.ndarray]:
        rings = np.asarray(rings, dtype=np.float64)
        if rings.shape[-1:] != (SONAR_COUNT,) or rings.ndim > 2:
            raise ValueError(f"rings must be (16,) or (N, 16), got {rings.shape}")
        batch = np.ascontiguousarray(rings.reshape(-1, SONAR_COUNT))
        views = np.arange(len(batch))
        rotations = np.full(len(batch), int(rotation) % SONAR_COUNT)
        velocity, experience = self._infer(batch, views, rotations)
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
        ring = _one_ring(ring)
        return self._infer(ring[None], self._one_ring, self._all_rotations)

    def perceive_ahead(self, ring: np.ndarray) -> np.ndarray:
        """Velocities (J,) m/s of one ring (16,) facing as it does: row 0 of `perceive`, bit for
        bit, at a sixteenth of the work."""
        ring = _one_ring(ring)
        return self._infer(ring[None], self._one_ring[:1], self._all_rotations[:1])[0][0]

    def explain(self, ring: np.ndarray) -> Explanation:
        """The memberships, fired rules and weighted averages behind velocities(ring)."""
        ring = _one_ring(ring)
        x = self._inputs(ring[None], 0)  # (n, T, 1) metres
        base, strength = self._firing.fire(x)
        velocity, experience = self._batch(ring, 0)
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
            tuple(velocity.tolist()),
            tuple(experience.tolist()),
        )

    def _fired_rules(self, t: int, base: int, strength: np.ndarray) -> list[FiredRule]:
        """Table t's rules among the corners from `base` with strengths (C,) above 0."""
        table = self._config.tables[t]
        live = np.flatnonzero(strength > 0)
        rules = base + self._firing.corners[live, t] - self._first_rows[t]
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


def _one_ring(ring: np.ndarray) -> np.ndarray:
    """One ring (16,) metres as float64, or ValueError saying what it is instead."""
    ring = np.asarray(ring, dtype=np.float64)
    if ring.shape != (SONAR_COUNT,):
        raise ValueError(f"ring must be ({SONAR_COUNT},), got {ring.shape}")
    return ring
