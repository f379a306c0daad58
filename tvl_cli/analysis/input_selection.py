"""Choosing each FAM table's inputs from learning logs, where the paper chose them by hand.

The paper (§3.3) picked the sonars of each trajectory's FAM, and the fuzzy sets of each, from
how a sonar ring sees flat walls. Here they are picked by how well a table fed by them
perceives its trajectory's velocity labels on episodes it was not trained on: greedy forward
selection over single sonars and the minima of two or three adjacent ones, each with one of
the shipped partitions, under one budget of rules for all tables together. A candidate table
is trained exactly as `tvl train` trains (the same labels, the same Fam.train), so what is
measured is what a robot would perceive.

Only the straight trajectory's table and the left ones are chosen; each right table is the
mirror image of its left one, as in the multi configuration. Symmetric training trains the
left table on the right trajectory's rings mirrored, so those are part of its data here too,
and the straight table, trained on every ring and its mirror image, takes only inputs whose
mirror images it also has: mirrored pairs, or groups that are their own mirror image.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import (
    BUILTIN_FAM_CONFIGS,
    MULTI,
    PARTITIONS,
    FamConfig,
    FamDesign,
    FamInput,
    FamTable,
    InputChoice,
    mirror_table,
    sonar_input,
)
from tvl_cli.core.fam_config_json import MAX_INPUTS_PER_TABLE, validate_fam_config
from tvl_cli.core.heard import HeardEpisode
from tvl_cli.core.robot_config import SONAR_COUNT, RobotConfig, mirror_sonar, mirror_trajectory
from tvl_cli.core.training import TrainParams, heard_labels, train_heard

# The paper's multi FAM is the reference: as many rules, unless the user gives a budget.
DEFAULT_BUDGET_RULES = MULTI.rule_count
# One sonar, or the nearest reading of two or three adjacent ones (the single FAM's groups).
GROUP_SIZES = (1, 2, 3)
# The partitions the shipped configurations use, dense near the robot; a new shape would be
# a second opinion on where the ring needs resolution.
SET_COUNTS = tuple(sorted(PARTITIONS))
# A quarter of each table's episodes (at least one) are held out to score candidates.
HELDOUT_FRACTION = 0.25
# A smaller drop of a table's held-out error is taken as none: it buys a few mm/s on one
# split of the episodes at the price of multiplying the table's rules.
MIN_GAIN_MPS = 0.002
# Exemplars a candidate table trains on, at most (about 1.5 hours of learning's worth for one
# table): past this a subsample drawn from the seed keeps a long log's design within minutes.
MAX_TRAIN_EXEMPLARS = 12_000


@dataclass(frozen=True, slots=True)
class HeldOutScore:
    """A configuration trained on the training episodes, perceiving the held-out ones."""

    config: str
    rules: int
    error_mps: float  # mean |perceived - label| over every held-out exemplar
    # the same, for each trajectory with held-out episodes
    error_by_trajectory_mps: tuple[tuple[str, float], ...]


@dataclass(frozen=True, slots=True)
class Design:
    """A configuration chosen from data, and how it and the shipped ones score held out."""

    config: FamConfig  # its `design` records the choices and what each bought
    train_episodes: int
    heldout_episodes: int
    candidates_scored: int  # candidate tables trained and scored in all
    scores: tuple[HeldOutScore, ...]  # the chosen configuration, then each shipped one


@dataclass(frozen=True, slots=True, eq=False)
class _Pool:
    """One chosen table's exemplars, split by episode: its trajectory's rings as read and its
    mirror trajectory's mirrored, which is what symmetric training feeds the table."""

    name: str
    copies: int  # 1 for the table that mirrors itself, else 2 (the right table is its mirror)
    train_rings: np.ndarray  # (N, 16) m
    train_labels: np.ndarray  # (N,) m/s
    heldout_rings: np.ndarray  # (H, 16) m
    heldout_labels: np.ndarray  # (H,) m/s


@dataclass(frozen=True, slots=True)
class _Candidate:
    groups: tuple[tuple[int, ...], ...]  # one sonar group, or a group and its mirror image
    sets: int

    def inputs(self) -> tuple[FamInput, ...]:
        return tuple(sonar_input(group, self.sets) for group in self.groups)

    @property
    def rule_factor(self) -> int:
        return self.sets ** len(self.groups)


@dataclass(slots=True)
class _Table:
    """A table being chosen: its inputs so far and their held-out error."""

    pool: _Pool
    inputs: list[FamInput]
    error_mps: float
    rules: int = 1  # of one copy of the table: the product of its inputs' set counts
    proposal: tuple[_Candidate, float] | None = None  # the best next input and its error
    proposed: bool = False  # `proposal` is up to date


_MIRRORED_RING = np.array([mirror_sonar(i) for i in range(SONAR_COUNT)])  # (16,) ring index


def design_inputs(
    labelled: Sequence[HeardEpisode],
    robot: RobotConfig,
    params: TrainParams,
    budget_rules: int = DEFAULT_BUDGET_RULES,
    seed: int = 1,
    name: str = "designed",
    logs_sha256: tuple[str, ...] = (),
) -> Design:
    """Choose every table's inputs from the episodes, each with the collision points its
    points label (core.training.labelled_episodes: every trajectory by the heard rule, the
    driven one by the paper's); BadInput if the budget cannot give each table one input, or
    if too few episodes label a table's trajectories to train on one and hold one out."""
    names = [t.name for t in robot.trajectories]
    count = len(names)
    designed = _designed(count)
    least = least_budget_rules(robot)
    if budget_rules < least:
        raise BadInput(
            f"--budget {budget_rules}: too small for one input per table "
            f"(at least {least} rules: {min(SET_COUNTS)} per table and its mirror)"
        )
    rng = np.random.default_rng(seed)
    # Held out by the trajectory driven, so that each table's own episodes are split in the
    # same proportion; every table then takes what each episode labels of it.
    split = [_split(labelled, j, names, rng) for j in designed]
    heldout_set = {i for _, part in split for i in part}
    # In log order, as `tvl train` would meet them.
    train = [h for i, h in enumerate(labelled) if i not in heldout_set]
    heldout = [h for i, h in enumerate(labelled) if i in heldout_set]
    exemplars = [
        _Exemplars(h.episode.fam_rings(), heard_labels(h, robot, params)) for h in labelled
    ]
    train_exemplars = [e for i, e in enumerate(exemplars) if i not in heldout_set]
    heldout_exemplars = [e for i, e in enumerate(exemplars) if i in heldout_set]
    tables = [_table(j, train_exemplars, heldout_exemplars, robot, rng) for j in designed]
    choices, scored = _choose(tables, budget_rules, params)

    by_name = {t.pool.name: FamTable(t.pool.name, tuple(t.inputs), (t.pool.name,)) for t in tables}
    config = FamConfig(
        name,
        tuple(
            by_name[n]
            if j in designed
            else mirror_table(by_name[names[mirror_trajectory(j, count)]], n)
            for j, n in enumerate(names)
        ),
        FamDesign(seed, budget_rules, logs_sha256, tuple(choices)),
    )
    validate_fam_config(config, names)
    return Design(
        config,
        len(train),
        len(heldout),
        scored,
        tuple(
            heldout_score(c, train, heldout, robot, params)
            for c in (config, *BUILTIN_FAM_CONFIGS.values())
        ),
    )


def heldout_score(
    config: FamConfig,
    train: Sequence[HeardEpisode],
    heldout: Sequence[HeardEpisode],
    robot: RobotConfig,
    params: TrainParams,
) -> HeldOutScore:
    """Train a whole FAM of `config` on `train` as `tvl train` does, and score it on every
    trajectory that `heldout`'s points label."""
    names = [t.name for t in robot.trajectories]
    fam = Fam(config, names, params.init_velocity_mps)
    for episode in train:
        train_heard(fam, episode, robot, params)
    rings = np.concatenate([h.episode.fam_rings() for h in heldout])  # (H, 16) m
    all_labels = np.concatenate([heard_labels(h, robot, params) for h in heldout])  # (H, T)
    points, trajectory = np.nonzero(~np.isnan(all_labels))
    perceived = fam.velocities(rings)[points, trajectory]  # m/s
    error = np.abs(perceived - all_labels[points, trajectory])
    total = np.bincount(trajectory, error, len(names))
    exemplars = np.bincount(trajectory, minlength=len(names))
    return HeldOutScore(
        config.name,
        config.rule_count,
        float(error.mean()),
        tuple((n, float(total[j] / exemplars[j])) for j, n in enumerate(names) if exemplars[j]),
    )


def least_budget_rules(robot: RobotConfig) -> int:
    """The fewest rules that give every table one input of the fewest sets."""
    count = len(robot.trajectories)
    return sum(_copies(j, count) * min(SET_COUNTS) for j in _designed(count))


def _designed(count: int) -> list[int]:
    """The trajectories whose tables are chosen: the left ones and the straight one."""
    return [j for j in range(count) if j <= mirror_trajectory(j, count)]


def _copies(j: int, count: int) -> int:
    """Tables that table j stands for: itself, and the mirror image of it unless straight."""
    return 1 if mirror_trajectory(j, count) == j else 2


def _split(
    labelled: Sequence[HeardEpisode], j: int, names: Sequence[str], rng: np.random.Generator
) -> tuple[list[int], list[int]]:
    """Indices of the episodes that drove trajectory j or its mirror, in log order: those to
    train on, and those held out."""
    pair = (j, mirror_trajectory(j, len(names)))
    mine = [i for i, h in enumerate(labelled) if h.episode.trajectory in pair]
    held = max(1, round(HELDOUT_FRACTION * len(mine)))
    out = set(rng.permutation(len(mine))[:held].tolist())
    return (
        [i for k, i in enumerate(mine) if k not in out],
        [i for k, i in enumerate(mine) if k in out],
    )


class _Exemplars(NamedTuple):
    """One episode as training reads it: what the FAM reads at each point, and the label of
    every trajectory there."""

    rings: np.ndarray  # (n, 16) m: the live ring, or the memory's virtual one
    labels: np.ndarray  # (n, T) m/s; NaN: not labelled


def _table(
    j: int,
    train: Sequence[_Exemplars],
    heldout: Sequence[_Exemplars],
    robot: RobotConfig,
    rng: np.random.Generator,
) -> _Table:
    name = robot.trajectories[j].name
    copies = _copies(j, len(robot.trajectories))
    train_rings, train_labels = _pooled(train, j, len(robot.trajectories))
    heldout_rings, heldout_labels = _pooled(heldout, j, len(robot.trajectories))
    if not (len(train_labels) and len(heldout_labels)):
        pair = (j, mirror_trajectory(j, len(robot.trajectories)))
        both = " or ".join(dict.fromkeys(robot.trajectories[k].name for k in pair))
        labelling = sum(1 for e in (*train, *heldout) if _labels_any(e, pair))
        raise BadInput(
            f"{labelling} episode(s) of {both}: at least 2 are needed to choose table "
            f"{name}'s inputs, one to train on and one to hold out (learn for longer)"
        )
    if len(train_labels) > MAX_TRAIN_EXEMPLARS:
        keep = np.sort(rng.choice(len(train_labels), MAX_TRAIN_EXEMPLARS, replace=False))
        train_rings, train_labels = train_rings[keep], train_labels[keep]
    pool = _Pool(name, copies, train_rings, train_labels, heldout_rings, heldout_labels)
    # With no input a table is one rule, which learns the mean label (eq. 2, every w = 1).
    return _Table(pool, [], float(np.abs(train_labels.mean() - heldout_labels).mean()))


def _labels_any(episode: _Exemplars, trajectories: tuple[int, ...]) -> bool:
    """Whether any point of the episode labels any of the trajectories."""
    return bool((~np.isnan(episode.labels[:, list(trajectories)])).any())


def _pooled(episodes: Sequence[_Exemplars], j: int, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Rings (N, 16) m and labels (N,) m/s that train table j, episode by episode: the points
    labelling trajectory j with their rings as read, those labelling its mirror with theirs
    mirrored (the straight table's own, both ways)."""
    mirror = mirror_trajectory(j, count)
    rings, labels = [], []
    for episode in episodes:
        own = ~np.isnan(episode.labels[:, j])
        rings.append(episode.rings[own])
        labels.append(episode.labels[own, j])
        mirrored = ~np.isnan(episode.labels[:, mirror])
        rings.append(episode.rings[mirrored][:, _MIRRORED_RING])
        labels.append(episode.labels[mirrored, mirror])
    return np.concatenate(rings), np.concatenate(labels)


def _choose(
    tables: list[_Table], budget_rules: int, params: TrainParams
) -> tuple[list[InputChoice], int]:
    """Add inputs one choice at a time, each the one that lowers the overall held-out error
    most within the budget, until none lowers its table's by MIN_GAIN_MPS; the choices, and
    how many candidate tables were scored."""
    choices: list[InputChoice] = []
    scored = 0
    while True:
        for table in tables:
            if not table.proposed:
                table.proposal, tried = _best(table, _room(tables, table, budget_rules), params)
                table.proposed = True
                scored += tried
        open_tables = [
            t for t in tables if t.proposal and (not t.inputs or _gain(t) >= MIN_GAIN_MPS)
        ]
        if not open_tables:
            return choices, scored
        # A table without inputs is no table at all, so those come first; then the largest
        # drop of the error over every held-out exemplar.
        table = max(
            open_tables, key=lambda t: (not t.inputs, len(t.pool.heldout_labels) * _gain(t))
        )
        assert table.proposal is not None
        candidate, error = table.proposal
        added = candidate.inputs()
        choices.append(
            InputChoice(table.pool.name, tuple(i.name for i in added), table.error_mps, error)
        )
        table.inputs.extend(added)
        table.rules *= candidate.rule_factor
        table.error_mps = error
        table.proposal, table.proposed = None, False
        for other in tables:
            # A proposal that no longer fits the budget is made again; one that fits is still
            # the best, since the budget only shrinks.
            if other.proposal is not None:
                grown = other.rules * other.proposal[0].rule_factor
                if grown > _room(tables, other, budget_rules):
                    other.proposed = False


def _gain(table: _Table) -> float:
    """How much the table's proposal lowers its held-out error, m/s."""
    return table.error_mps - table.proposal[1] if table.proposal else -np.inf


def _room(tables: list[_Table], table: _Table, budget_rules: int) -> int:
    """The most rules one copy of `table` may have, the others' rules as they stand."""
    others = sum(_cost(t) for t in tables if t is not table)
    return (budget_rules - others) // table.pool.copies


def _cost(table: _Table) -> int:
    """Rules of the table and its mirror; one input of the fewest sets kept for an empty one."""
    return table.pool.copies * (table.rules if table.inputs else min(SET_COUNTS))


def _best(
    table: _Table, room_rules: int, params: TrainParams
) -> tuple[tuple[_Candidate, float] | None, int]:
    """The candidate of lowest held-out error that fits `room_rules` (for one copy of the
    table), and how many were scored."""
    best: tuple[_Candidate, float] | None = None
    used = {s for i in table.inputs for s in i.sonars}
    candidates = [
        c
        for c in _candidates(table.pool.copies == 1, used)
        if table.rules * c.rule_factor <= room_rules
        and len(table.inputs) + len(c.groups) <= MAX_INPUTS_PER_TABLE
    ]
    for candidate in candidates:
        error = _heldout_error(table.pool, (*table.inputs, *candidate.inputs()), params)
        if best is None or error < best[1]:
            best = (candidate, error)
    return best, len(candidates)


def _candidates(self_mirrored: bool, used: set[int]) -> list[_Candidate]:
    """Every sonar group not sharing a sonar with the inputs chosen, with every partition;
    for a table that mirrors itself, only groups with their mirror image (or that are one)."""
    found: list[_Candidate] = []
    seen: set[frozenset[int]] = set()
    for size in GROUP_SIZES:
        for start in range(SONAR_COUNT):
            group = tuple((start + k) % SONAR_COUNT for k in range(size))
            # Read from the other end, so that the mirror image runs counter-clockwise too.
            image = tuple(mirror_sonar(s) for s in reversed(group))
            groups: tuple[tuple[int, ...], ...] = (group,)
            if self_mirrored and set(image) != set(group):
                if set(image) & set(group):
                    continue  # a group overlapping its own mirror image is no pair
                groups = (group, image)
            sonars = frozenset(s for g in groups for s in g)
            if sonars & used or sonars in seen:
                continue
            seen.add(sonars)
            found += [_Candidate(groups, sets) for sets in SET_COUNTS]
    return found


def _heldout_error(pool: _Pool, inputs: tuple[FamInput, ...], params: TrainParams) -> float:
    """Mean |perceived - label| m/s on the pool's held-out exemplars of a table with these
    inputs, trained on its training exemplars by Fam.train as `tvl train` would."""
    table = FamTable(pool.name, inputs, (pool.name,))
    fam = Fam(FamConfig(pool.name, (table,)), (pool.name,), params.init_velocity_mps)
    # Not symmetric: the pool already holds the mirror trajectory's rings mirrored, which is
    # what symmetric training of the whole FAM gives this table.
    fam.train(pool.train_rings, np.zeros(len(pool.train_labels), np.intp), pool.train_labels, False)
    return float(np.abs(fam.velocities(pool.heldout_rings)[:, 0] - pool.heldout_labels).mean())
