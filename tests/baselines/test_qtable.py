"""Q-learning's pure parts: the state of a ring, the greedy choice and the update."""

from __future__ import annotations

import numpy as np
import pytest

from tvl_cli.baselines.qtable import (
    QParams,
    RuleStates,
    epsilon_greedy,
    greedy,
    preference_order,
    q_update,
)
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.robot_config import ALL_TRAJECTORY_NAMES

TABLE = SINGLE.tables[0]


def test_q_update_matches_the_formula_by_hand() -> None:
    q = np.zeros((4, 3))
    q[1, 2] = 0.5
    q[3] = [0.2, -1.0, 0.7]
    params = QParams(learning_rate=0.25, discount=0.9)
    q_update(q, 1, 2, 0.06, 3, params)
    assert q[1, 2] == pytest.approx(0.5 + 0.25 * (0.06 + 0.9 * 0.7 - 0.5))
    assert np.count_nonzero(q) == 4  # nothing else moved


def test_a_bump_ends_the_episode_without_bootstrapping() -> None:
    q = np.full((2, 2), 3.0)
    q_update(q, 0, 1, -6.0, None, QParams(learning_rate=0.5))
    assert q[0, 1] == pytest.approx(3.0 + 0.5 * (-6.0 - 3.0))


def test_state_of_a_ring_by_hand() -> None:
    ring = np.full(16, 4.0)
    ring[[15, 0, 1]] = [0.7, 0.5, 0.9]  # front 0.5: N (0.86) over M (0.14)
    ring[[2, 3, 4]] = 1.5  # front-left: F (0.625) over M
    ring[6] = 0.3  # rear-left: N (0.89)
    ring[13] = 0.9  # front-right: M (0.8) over N
    # rear-right reads 4.0: F. Sets (1, 3, 0, 2, 2) of shape (5, 4, 3, 3, 4).
    assert RuleStates(TABLE).one(ring) == (((1 * 4 + 3) * 3 + 0) * 3 + 2) * 4 + 2


def test_state_is_the_strongest_rule_the_fam_fires() -> None:
    rings = np.random.default_rng(5).uniform(0.15, 4.0, size=(200, 16))
    fam = Fam(SINGLE, ALL_TRAJECTORY_NAMES)
    states = RuleStates(TABLE).of(rings)
    for ring, state in zip(rings, states, strict=True):
        fired = {rule.rule: rule.strength for rule in fam.explain(ring).rules}
        assert fired[int(state)] == max(fired.values())


def test_greedy_ties_go_straight_on_first() -> None:
    order = preference_order(7)
    assert order.tolist() == [3, 2, 4, 1, 5, 0, 6]
    assert greedy(np.zeros(7), order) == 3
    assert greedy(np.array([0.0, 0.1, 0.0, 0.0, 0.0, 0.1, 0.0]), order) == 1


def test_epsilon_greedy_explores_only_with_chance_epsilon() -> None:
    q_row = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
    order = preference_order(7)
    rng = np.random.default_rng(0)
    assert {epsilon_greedy(q_row, order, 0.0, rng) for _ in range(50)} == {3}
    assert {epsilon_greedy(q_row, order, 1.0, rng) for _ in range(200)} == set(range(7))
