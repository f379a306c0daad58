"""Autopsies summed over runs, from the records each run's JSON carries."""

from __future__ import annotations

from tvl_cli.analysis.autopsy import (
    CAUSES,
    DRIVE_FAST,
    GOAL_FAILURES,
    MEMORY,
    RATED_FAST,
    REFLEX,
    SLOW_CAUSES,
    STALLED,
    TIGHT,
    TIME_CLASSES,
    Autopsy,
    Contact,
    ContactFacts,
    tally,
)
from tvl_cli.core.contacts import BUMP, NEAR_MISS


def _contact(
    cause: str, event: str = BUMP, true_mps: float = 0.0, experience: float = 3.0
) -> Contact:
    facts = ContactFacts(
        1, 0.1, event, "slant", "policy", None, "T0", True, True, True, 0.5, true_mps, experience
    )
    return Contact(facts, cause)


def test_tally_sums_contacts_time_slow_time_and_goal_failures_over_the_runs_records() -> None:
    first = Autopsy(
        (_contact(RATED_FAST, experience=0.5), _contact(REFLEX, NEAR_MISS)),
        {name: 1.0 for name in TIME_CLASSES},
        slow_time_s={**dict.fromkeys(SLOW_CAUSES, 0.0), MEMORY: 1.5, TIGHT: 0.5},
    )
    second = Autopsy(
        (_contact(RATED_FAST, true_mps=0.2),),
        {**{name: 0.0 for name in TIME_CLASSES}, DRIVE_FAST: 2.5},
        goal_failure=STALLED,
        slow_time_s={**dict.fromkeys(SLOW_CAUSES, 0.0), MEMORY: 2.0},
    )
    # A run's record made before slow time was told, which a resumed bench may still hold.
    earlier = {**second.to_dict(), "contacts": [], "causes": [], "time": []}
    del earlier["slow_time"]
    summed = tally([first.to_dict(), second.to_dict(), earlier])
    assert summed["causes"] == {c: {RATED_FAST: 2, REFLEX: 1}.get(c, 0) for c in CAUSES}
    assert summed["time_s"] == {n: 3.5 if n == DRIVE_FAST else 1.0 for n in TIME_CLASSES}
    assert summed["slow_time_s"] == {c: {MEMORY: 3.5, TIGHT: 0.5}.get(c, 0.0) for c in SLOW_CAUSES}
    assert summed["goal_failures"] == {r: 2 * int(r == STALLED) for r in GOAL_FAILURES}
    # The rated-fast contacts: the truth under their ratings, and one in two barely trained.
    assert summed["rated_fast"] == {
        "contacts": 2,
        "median_true_mps": 0.1,
        "median_rated_mps": 0.5,
        "untrained_share": 0.5,
        "by_trajectory": [{"trajectory": "T0", "contacts": 2}],
    }


def test_tally_counts_the_rated_fast_contacts_by_trajectory_most_first() -> None:
    def met_on(*trajectories: str | None) -> dict:
        contacts = [{"cause": RATED_FAST, "trajectory": t} for t in trajectories]
        return {**Autopsy((), dict.fromkeys(TIME_CLASSES, 0.0)).to_dict(), "contacts": contacts}

    # A row made before the trajectory was kept counts toward the contacts, not the table.
    older = {"cause": RATED_FAST, "rated_mps": 0.5, "true_mps": 0.0, "experience": 2.0}
    summed = tally([met_on("T3L", "T1R", None), met_on("T3L", "T2R", "T1R", "T3L"),
                    {**met_on(), "contacts": [older]}])  # fmt: skip
    assert summed["rated_fast"]["contacts"] == 8
    assert summed["rated_fast"]["by_trajectory"] == [
        {"trajectory": "T3L", "contacts": 3},
        {"trajectory": "T1R", "contacts": 2},
        {"trajectory": "T2R", "contacts": 1},
    ]
