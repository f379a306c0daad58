"""The JSON documents of the commands' `--json`, each in the shape its schema fixes
(tvl_cli/schemas/): what the command was given, what it wrote, what it found. Those of the
commands that run grids of cells, sweep and bench, are grid_documents'.

Every input is echoed, files as their path and SHA-256, so that a saved document can be
traced to the run that made it.
"""

from __future__ import annotations

import hashlib
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Any

from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS
from tvl_cli.core.robot_profiles import profile_name
from tvl_cli.io.json_documents import document, input_file, optional_file, output_path
from tvl_cli.io.loglayout import ended_status

if TYPE_CHECKING:
    # Named for their types only: a command's `--help` imports this module.
    import numpy as np

    from tvl_cli.analysis.autopsy import Autopsy
    from tvl_cli.analysis.famdiff import FamDifference
    from tvl_cli.analysis.rules import Rule
    from tvl_cli.commands.baseline import DwaReport, QLearnReport
    from tvl_cli.commands.demo import DemoResult
    from tvl_cli.commands.design import DesignSummary
    from tvl_cli.commands.explain import StepExplanation
    from tvl_cli.commands.export import Exported
    from tvl_cli.commands.learn import LearnResult
    from tvl_cli.commands.replay import Replay
    from tvl_cli.commands.run import RunRequest, RunResult
    from tvl_cli.commands.train import TrainSummary
    from tvl_cli.commands.world_export import Exported as WorldExported
    from tvl_cli.commands.world_import import Imported, ImportRequest
    from tvl_cli.core.fired_rules import Explanation
    from tvl_cli.io.famfile import FamFile
    from tvl_cli.io.log_sessions import RepeatedSession
    from tvl_cli.sim.worldmap import WorldMap


def world_new_json(options: dict[str, Any], output: Path, counts: dict[str, int]) -> dict[str, Any]:
    return document("world new", options, outputs={"world": str(output)}, counts=counts)


def world_show_json(file: Path, world: dict[str, Any]) -> dict[str, Any]:
    return document("world show", {"world": input_file(file)}, world=world)


def world_check_json(file: Path, counts: dict[str, int]) -> dict[str, Any]:
    return document("world check", {"world": input_file(file)}, ok=True, counts=counts)


def world_render_json(file: Path, output: Path, counts: dict[str, int]) -> dict[str, Any]:
    return document(
        "world render", {"world": input_file(file)}, outputs={"picture": str(output)}, counts=counts
    )


def world_import_json(request: ImportRequest, imported: Imported) -> dict[str, Any]:
    inputs = {
        "map_yaml": input_file(request.map_yaml),
        "image": input_file(imported.map.meta.image),
        "start": None if request.start is None else list(request.start),
        "cell_m": request.cell_m,
        "crop_m": None if request.crop is None else list(request.crop),
        "name": request.name,
    }
    return document(
        "world import", inputs, outputs={"world": str(request.output)}, **imported.to_dict()
    )


def world_export_json(exported: WorldExported) -> dict[str, Any]:
    outputs = {"map_yaml": str(exported.map_yaml), "image": str(exported.image)}
    return document(
        "world export", {"world": input_file(exported.world)}, outputs=outputs, **exported.to_dict()
    )


def learning(result: LearnResult) -> dict[str, Any]:
    """What a learning session did (`tvl learn`, and `tvl demo`'s learning)."""
    s = result.summary
    return {
        "session": result.session,
        "status": result.status,
        "episodes": s.episodes,
        "collisions": s.collisions,
        "exemplars": s.exemplars,
        "sim_minutes": s.sim_s / 60.0,
        "coverage": result.coverage,
        "wall_s": result.wall_s,
        "minutes": [
            {"session": result.session, **asdict(m), "minute": m.minute + 1, "coverage": c}
            for m, c in zip(s.minutes, result.minute_coverage, strict=True)
        ],
    }


def learn_json(result: LearnResult) -> dict[str, Any]:
    r = result.request
    inputs = {
        "world": _world_input(r.world),
        "seed": r.seed,
        **_config(r.config),
        **r.learn.to_dict(),
        "training": r.train.settings(),
        "from_fam": optional_file(r.from_fam),
        "method": result.method,
        "robot": profile_name(r.body),
    }
    outputs = {"log": str(r.log), "fam": output_path(r.fam_out)}
    return document("learn", inputs, outputs=outputs, **learning(result))


def _world_input(world: Path | WorldMap) -> dict[str, str]:
    """A world file as read; a generated world by its name, and the digest of its text."""
    if isinstance(world, Path):
        return input_file(world)
    return {"path": world.name, "sha256": hashlib.sha256(world.text.encode()).hexdigest()}


def _config(spec: str) -> dict[str, Any]:
    """A FAM configuration as given: a shipped one's name, or a file read."""
    return {
        "config": spec,
        "config_file": None if spec in BUILTIN_FAM_CONFIGS else input_file(spec),
    }


def _repeats(found: list[RepeatedSession]) -> list[dict[str, str]]:
    return [asdict(r) for r in found]


def train_json(
    summary: TrainSummary,
    logs: tuple[Path, ...],
    config: str,
    until_minute: float | None,
    output: Path,
) -> dict[str, Any]:
    inputs = {
        "logs": [input_file(log) for log in logs],
        **_config(config),
        "training": summary.training.settings(),
        "until_minute": until_minute,
        "method": summary.method_record(),
    }
    return document(
        "train",
        inputs,
        outputs={"fam": str(output)},
        config=summary.fam.config.name,
        episodes=summary.episodes,
        exemplars=summary.exemplars,
        rules_touched=summary.rules_touched,
        rules_total=summary.rules_total,
        wall_s=summary.wall_s,
        repeated_sessions=_repeats(summary.repeated_sessions),
    )


def design_json(
    summary: DesignSummary, logs: tuple[Path, ...], budget: int, seed: int
) -> dict[str, Any]:
    design = summary.design
    config = design.config
    assert config.design is not None
    inputs = {"logs": [input_file(log) for log in logs], "budget_rules": budget, "seed": seed}
    return document(
        "design",
        inputs,
        outputs={"config": str(summary.output)},
        config=config.name,
        rules=config.rule_count,
        train_episodes=design.train_episodes,
        heldout_episodes=design.heldout_episodes,
        candidates_scored=design.candidates_scored,
        tables=[
            {
                "name": t.name,
                "inputs": [{"name": i.name, "sets": len(i.partition.names)} for i in t.inputs],
                "rules": t.rule_count,
            }
            for t in config.tables
        ],
        choices=[asdict(c) for c in config.design.choices],
        heldout=[
            {
                "config": s.config,
                "rules": s.rules,
                "error_mps": s.error_mps,
                "error_by_trajectory": [
                    {"trajectory": t, "error_mps": e} for t, e in s.error_by_trajectory_mps
                ],
            }
            for s in design.scores
        ],
        repeated_sessions=_repeats(summary.repeated_sessions),
        wall_s=summary.wall_s,
    )


def run_json(request: RunRequest, result: RunResult) -> dict[str, Any]:
    """The run's metrics at the top (as results files gather them), its inputs beside."""
    inputs = {
        "fam": input_file(request.fam),
        "world": input_file(request.world),
        **result.options,
        "learn": request.learn is not None,
        "method": result.method,
    }
    outputs = {
        "png": output_path(request.png),
        "trace": output_path(request.trace),
        "log": output_path(request.learn.log if request.learn else None),
    }
    status = ended_status(result.stopped_by)
    return document("run", inputs, outputs=outputs, status=status, **result.to_dict())


def replay_json(
    summary: Replay,
    file: Path,
    session: str | None,
    pictures: dict[str, Path | None],
) -> dict[str, Any]:
    inputs = {"file": input_file(file), "session": session}
    outputs = {name: output_path(path) for name, path in pictures.items()}
    return document("replay", inputs, outputs=outputs, **summary.to_dict())


def explain_json(found: StepExplanation, trace: Path, moment: dict[str, Any]) -> dict[str, Any]:
    inputs = {"run": input_file(trace), "fam": input_file(found.fam), "contacts": False, **moment}
    return document("explain", inputs, step=found.to_dict(), autopsy=None)


def autopsy_json(autopsy: Autopsy, trace: Path) -> dict[str, Any]:
    inputs = {"run": input_file(trace), "fam": None, "contacts": True}
    return document("explain", inputs, step=None, autopsy=autopsy.to_dict())


def inspect_json(
    fam: Path,
    loaded: FamFile,
    options: dict[str, Any],
    ring: np.ndarray | None,
    rules: list[Rule] | None,
    explanation: Explanation | None,
    png: Path | None,
) -> dict[str, Any]:
    """A FAM's configuration and provenance, and its rules or one ring explained (--explain),
    the other null."""
    explained = None if ring is None else [float(r) for r in ring]
    return document(
        "inspect",
        {"fam": input_file(fam), **options, "explain_ring_m": explained},
        outputs={"png": output_path(png)},
        config=loaded.fam.config.to_dict(),
        method=loaded.made_by.record(),
        provenance=loaded.provenance,
        rules=None if rules is None else [r.to_dict() for r in rules],
        explanation=None if explanation is None else explanation.to_dict(),
    )


def diff_json(difference: FamDifference, first: Path, second: Path, top: int) -> dict[str, Any]:
    inputs = {
        "first": input_file(first),
        "second": input_file(second),
        "tolerance_mps": difference.tolerance_mps,
        "top": top,
    }
    return document("diff", inputs, **difference.to_dict())


def demo_json(result: DemoResult) -> dict[str, Any]:
    """The learning, then each run's metrics as `tvl run --json` prints them."""
    from tvl_cli.commands.demo import DEMO_SEED, RUN_MINUTES

    learnt = result.learning.request
    inputs = {
        "world": _world_input(learnt.world),
        "seed": DEMO_SEED,
        "learn_minutes": learnt.learn.minutes,
        "run_minutes": RUN_MINUTES,
    }
    return document(
        "demo",
        inputs,
        outputs={"directory": str(result.directory), "log": str(learnt.log)},
        learning=learning(result.learning),
        runs=[
            {
                "config": r.config,
                "behaviour": r.behaviour,
                "threshold": r.threshold,
                "fam": str(r.fam),
                "png": str(r.png),
                **asdict(r.metrics),
            }
            for r in result.rows
        ],
    )


def _baseline_inputs(world: Path, seed: int, method: dict[str, Any]) -> dict[str, Any]:
    return {"world": input_file(world), "seed": seed, "method": method}


def dwa_json(
    report: DwaReport,
    world: Path,
    seed: int,
    options: dict[str, Any],
    png: Path | None,
) -> dict[str, Any]:
    inputs = {**_baseline_inputs(world, seed, report.method), **options}
    return document(
        "baseline dwa", inputs, outputs={"png": output_path(png)}, **asdict(report.metrics)
    )


def qlearn_json(
    report: QLearnReport,
    world: Path,
    seed: int,
    options: dict[str, Any],
    png: Path | None,
) -> dict[str, Any]:
    inputs = {**_baseline_inputs(world, seed, report.method), **options}
    return document(
        "baseline qlearn", inputs, outputs={"png": output_path(png)}, **report.to_dict()
    )


def export_json(exported: Exported) -> dict[str, Any]:
    return document(
        "export",
        {"run": input_file(exported.run)},
        outputs={"mcap": str(exported.output)},
        steps=exported.steps,
        messages=[{"topic": topic, "messages": n} for topic, n in exported.messages.items()],
    )


def figure_json(
    name: str, results: Path, output: Path, table: Path | None, summary: str
) -> dict[str, Any]:
    return document(
        "figure",
        {"figure": name, "results": input_file(results)},
        outputs={"picture": str(output), "table": output_path(table)},
        summary_markdown=summary,
    )
