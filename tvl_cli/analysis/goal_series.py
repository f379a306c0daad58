"""Goal seeking (Figure 22): the goal runs as series, one for each TVL configuration by each
method and echo memory, and one for DWA."""

from __future__ import annotations

from tvl_cli.analysis.aggregation import distinct, select
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.result_text import method_label, methods_of


def goal_methods(rows: list[Row]) -> list[tuple[str, list[Row]]]:
    """(label, goal runs) for each TVL configuration by each method, and DWA."""
    goal_runs = select(rows, behaviour="goal")
    tvl = select(goal_runs, kind="tvl")
    methods = [
        (
            f"TVL {config}, {method_label(method)}{_reading(memory)}",
            select(tvl, config=config, method=method, run_memory=memory),
        )
        for method in methods_of(tvl)
        for config in distinct(select(tvl, method=method), "config", ("single", "multi"))
        for memory in _run_memories(select(tvl, method=method, config=config))
    ]
    dwa = select(goal_runs, kind="dwa")
    return methods + ([("DWA", dwa)] if dwa else [])


def _run_memories(runs: list[Row]) -> list[str | None]:
    """The echo memories the runs read through: None (their FAM's own) first."""
    own: list[str | None] = [None] if any(r.get("run_memory") is None for r in runs) else []
    return own + distinct(runs, "run_memory")


def _reading(run_memory: str | None) -> str:
    """How a label says a run read through another echo memory than its FAM learnt with."""
    return "" if run_memory is None else f", run with memory {run_memory}"
