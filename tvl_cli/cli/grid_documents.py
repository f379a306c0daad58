"""The JSON documents of `tvl sweep` and `tvl bench`, the commands that run grids of cells,
in the shapes their schemas fix (tvl_cli/schemas/): the grid and where it ran, the files it
wrote, and what its cells found."""

from __future__ import annotations

from dataclasses import asdict
from typing import TYPE_CHECKING, Any

from tvl_cli.core.method import method_record
from tvl_cli.io.json_documents import document, input_file, output_path

if TYPE_CHECKING:
    # Named for their types only: a command's `--help` imports this module.
    from tvl_cli.bench.claims_suite import ClaimsResult
    from tvl_cli.bench.generalization_suite import GeneralizationResult
    from tvl_cli.bench.suite_runner import BenchRun, Where
    from tvl_cli.sweep.runner import SweepRequest, SweepResult


def sweep_json(result: SweepResult, request: SweepRequest) -> dict[str, Any]:
    inputs = {
        "grid": input_file(request.grid),
        "out": str(request.out),
        "workers": request.workers if request.scheduler is None else None,
        "scheduler": request.scheduler,
        "scheduler_timeout_s": request.scheduler_timeout_s,
        "max_cells": request.max_cells,
        "size": request.size,
        "measures": None if request.measures is None else list(request.measures),
        "plot": None if request.plot is None else asdict(request.plot),
    }
    outputs = {"files": [str(path) for path in result.files], "plot": output_path(result.plot)}
    return document(
        "sweep",
        inputs,
        outputs=outputs,
        cells=result.cells,
        done=result.done,
        skipped=result.skipped,
    )


def _where_inputs(where: Where) -> dict[str, Any]:
    return {
        "out": str(where.out),
        "workers": where.workers if where.scheduler is None else None,
        "scheduler": where.scheduler,
        "scheduler_timeout_s": where.scheduler_timeout_s,
    }


def _bench_run(run: BenchRun) -> dict[str, Any]:
    return {
        "outputs": {"files": [str(path) for path in run.files]},
        "cells": run.cells,
        "done": run.done,
        "skipped": run.skipped,
        "wall_s": run.wall_s,
        "cpu_s": run.cpu_s,
    }


def bench_generalization_json(result: GeneralizationResult, where: Where) -> dict[str, Any]:
    request, plan = result.request, result.plan
    inputs = {
        "set": request.world_set,
        "worlds": plan.world_seeds,
        "trials": plan.trials,
        "size": request.size,
        "learn_minutes": plan.size.learn_minutes,
        "run_minutes": plan.size.run_minutes,
        "threshold": request.threshold,
        "method_name": request.method_name,
        "method": method_record(request.method),
        "configs": [config.name for config in request.configs],
        "controllers": [
            {"name": c.name, "kind": c.kind, "spec": c.spec} for c in request.controllers
        ],
        "observe": None if request.observe is None else method_record(request.observe),
        "references": list(request.references),
        **_where_inputs(where),
    }
    return document(
        "bench generalization",
        inputs,
        **_bench_run(result.run),
        entries=[asdict(entry) for entry in plan.entries],
        figures=[figures.to_dict() for figures in result.figures],
        rows=result.run.rows,
    )


def bench_claims_json(result: ClaimsResult, where: Where) -> dict[str, Any]:
    request = result.request
    inputs = {
        "methods": list(request.methods),
        "claims": list(request.claims),
        "size": request.size,
        "trials": result.trials,
        **_where_inputs(where),
    }
    return document(
        "bench claims",
        inputs,
        **_bench_run(result.run),
        verdicts=[row.to_dict() for row in result.verdicts],
        rows=result.run.rows,
    )
