"""The bench's autopsy table, from autopsies summed as a bench sums its rows."""

from __future__ import annotations

from tvl_cli.analysis.autopsy import RATED_FAST, TIME_CLASSES, Autopsy, tally
from tvl_cli.analysis.generalization import Figures
from tvl_cli.cli.bench_view import autopsy_table


def _figures(entry: str, contacts: list[dict]) -> Figures:
    run = {**Autopsy((), dict.fromkeys(TIME_CLASSES, 1.0)).to_dict(), "contacts": contacts}
    run["causes"] = [{"cause": RATED_FAST, "contacts": len(contacts)}]
    return Figures(
        entry, "method", False, "default", "single", 1, 0, {}, 0, 0, None, None, None, None,
        None, tally([run]),
    )  # fmt: skip


def test_the_table_names_the_trajectory_most_rated_fast_contacts_were_met_on() -> None:
    met = [{"cause": RATED_FAST, "trajectory": t} for t in ("T3L", "T3L", "T3L", "T2R", "T0")]
    older = [{"cause": RATED_FAST, "rated_mps": 0.5, "true_mps": 0.0, "experience": 2.0}]
    _, rows = autopsy_table([_figures("lifted", met), _figures("before", older)])
    assert ("rated-fast: most often on", "T3L (60%)", "–") in rows
    assert ("contacts: rated-fast", "5", "1") in rows
