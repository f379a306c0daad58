"""Tabular Q-learning over the rules of a FAM table: states, greedy choice and the update,
and the learner that holds them (QTable), which the baseline's policy and the Gymnasium
agent both learn with.

A ring's state is the table's rule that fires strongest for it. A rule's strength is the
minimum of its inputs' memberships, and each input picks its fuzzy set independently, so the
strongest rule takes, for every input, the set with the larger membership (the lower one on a
tie, at exactly half way).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tvl_cli.core.fam_config import FamTable
from tvl_cli.core.fuzzy import StackedPartitions
from tvl_cli.core.learn_params import BACKOFF_M
from tvl_cli.core.reward import COLLISION_PENALTY_M


@dataclass(frozen=True, slots=True)
class QParams:
    """Learning settings. Rewards are in metres: progress, less a penalty for each bump."""

    learning_rate: float = 0.2  # alpha
    # gamma: 0.95 looks about 20 control periods (2 s, 1.2 m at top speed) ahead, enough to
    # turn away from a wall before reaching it.
    discount: float = 0.95
    epsilon: float = 0.1  # chance of a random action while learning
    collision_penalty: float = COLLISION_PENALTY_M
    reverse_m: float = BACKOFF_M  # backed off along the path after a bump, as TVL learning does


class RuleStates:
    """Rings (N, 16) metres -> the flat index (N,) of the strongest rule of one FAM table.

    The flat index is the C-order ravel over the table's shape, as in the FAM.
    """

    def __init__(self, table: FamTable) -> None:
        self.table = table
        groups = max(len(i.sonars) for i in table.inputs)
        # (n, g) sonars per input, a group padded by repeating its first sonar (same minimum)
        self._sonars = np.array(
            [i.sonars + (i.sonars[0],) * (groups - len(i.sonars)) for i in table.inputs],
            dtype=np.intp,
        )
        self._partitions = StackedPartitions.of([i.partition for i in table.inputs])

    @property
    def count(self) -> int:
        return self.table.rule_count

    def of(self, rings_m: np.ndarray) -> np.ndarray:
        """(N,) rule indices of rings (N, 16) metres."""
        rings_m = np.asarray(rings_m, dtype=np.float64)
        x = rings_m[:, self._sonars].min(axis=2).T  # (n, N) each input's group minimum, metres
        lower, upper = self._partitions.fuzzify(x)
        sets = lower + (upper > 0.5)  # (n, N) the stronger set of each input
        return np.ravel_multi_index(tuple(sets), self.table.shape)

    def one(self, ring_m: np.ndarray) -> int:
        """The rule index of one ring (16,) metres."""
        return int(self.of(np.asarray(ring_m)[None])[0])


def preference_order(actions: int) -> np.ndarray:
    """Actions from the middle one outwards (straight ahead first, left before right)."""
    centre = (actions - 1) / 2
    return np.argsort(np.abs(np.arange(actions) - centre), kind="stable")


def greedy(q_row: np.ndarray, order: np.ndarray) -> int:
    """The best action of a state; ties (as in a state never visited) go to the earliest in
    `order`, so an unknown state drives straight on."""
    return int(order[np.argmax(q_row[order])])


def epsilon_greedy(
    q_row: np.ndarray, order: np.ndarray, epsilon: float, rng: np.random.Generator
) -> int:
    """A random action with chance epsilon, else the greedy one."""
    if rng.random() < epsilon:
        return int(rng.integers(len(q_row)))
    return greedy(q_row, order)


def q_update(
    q: np.ndarray,
    state: int,
    action: int,
    reward: float,
    next_state: int | None,
    params: QParams,
) -> None:
    """Q[s, a] += alpha (r + gamma max_a' Q[s', a'] - Q[s, a]), in place on q (S, A).

    next_state None ends the episode (a bump): nothing is bootstrapped after it.
    """
    future = 0.0 if next_state is None else params.discount * float(q[next_state].max())
    q[state, action] += params.learning_rate * (reward + future - q[state, action])


class QTable:
    """A table of action values over a FAM table's rules, learnt one step at a time.

    Actions are tried straight ahead first (preference_order): a state never visited drives
    straight on.
    """

    def __init__(
        self, states: RuleStates, actions: int, params: QParams, q: np.ndarray | None = None
    ) -> None:
        """`q` (rules, actions) to learn into in place, shared with its owner; a zero table
        by default."""
        self.states = states
        self.params = params
        self.q = np.zeros((states.count, actions)) if q is None else q
        self._order = preference_order(actions)

    def state(self, ring_m: np.ndarray) -> int:
        """The state of a ring (16,) metres: its strongest rule."""
        return self.states.one(ring_m)

    def act(self, state: int, rng: np.random.Generator | None = None) -> int:
        """The action for a state: epsilon-greedy drawing from `rng`, greedy without one."""
        if rng is None:
            return greedy(self.q[state], self._order)
        return epsilon_greedy(self.q[state], self._order, self.params.epsilon, rng)

    def learn(self, state: int, action: int, reward: float, next_state: int | None) -> None:
        """One step's update; `next_state` None ends the episode (a bump)."""
        q_update(self.q, state, action, reward, next_state, self.params)
