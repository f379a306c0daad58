"""`tvl design`: choose each FAM table's inputs from learning logs; write the configuration."""

from __future__ import annotations

import json
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from tvl_cli.agent.perception import perceived_session
from tvl_cli.analysis.input_selection import DEFAULT_BUDGET_RULES, Design, design_inputs
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config_json import fam_config_from_json
from tvl_cli.core.method import NOT_GIVEN, Method, MethodChoice, method_record
from tvl_cli.core.training import labelled_episodes, train_params
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.json_documents import document, input_file
from tvl_cli.io.log_sessions import (
    RepeatedSession,
    common_robot,
    distinct_sessions,
    session_to_train,
    training_method,
)
from tvl_cli.io.logreader import read_log, refuse_repeated


@dataclass(frozen=True, slots=True)
class DesignSummary:
    logs: tuple[Path, ...]
    budget_rules: int
    seed: int
    design: Design
    output: Path
    made_by: Method  # the method whose labels and memory the inputs were chosen by
    mixed: list[str]  # the method's fields in which the logs' learning sessions differ
    repeated_sessions: list[RepeatedSession]  # used once
    wall_s: float

    def document(self) -> dict[str, Any]:
        design = self.design
        config = design.config
        assert config.design is not None
        inputs = {
            "logs": [input_file(log) for log in self.logs],
            "budget_rules": self.budget_rules,
            "seed": self.seed,
            "method": method_record(self.made_by, mixed=self.mixed),
        }
        return document(
            "design",
            inputs,
            outputs={"config": str(self.output)},
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
            repeated_sessions=[asdict(found) for found in self.repeated_sessions],
            wall_s=self.wall_s,
        )


def design_from_logs(
    paths: Sequence[Path],
    output: Path,
    budget_rules: int = DEFAULT_BUDGET_RULES,
    seed: int = 1,
    overwrite: bool = False,
    method: MethodChoice = NOT_GIVEN,
) -> DesignSummary:
    """Choose the inputs from every episode of the logs, read and labelled as `tvl train`
    with the same method reads and labels them (through the method's memory, by its labels'
    rule), and write the configuration as JSON that `--config` reads, named after it."""
    started = time.perf_counter()
    if not paths:
        raise BadInput("no learning log given: name at least one LOG")
    logs = [read_log(path) for path in paths]
    refuse_repeated([(log.path, log.sha256) for log in logs], "log")
    robot = common_robot(logs)
    made_by, differing = training_method(logs, method)
    params = train_params(made_by)
    sessions, repeats = distinct_sessions(logs)
    design = design_inputs(
        [
            heard
            for s in sessions
            for heard in labelled_episodes(
                perceived_session(session_to_train(s), made_by.memory, robot), robot, params
            )
        ],
        robot,
        params,
        budget_rules,
        seed,
        output.stem,
        tuple(log.sha256 for log in logs),
    )
    text = json.dumps(design.config.to_dict(), indent=1) + "\n"
    # Read back as `--config FILE.json` will read it, so that a file written is one it takes.
    fam_config_from_json(text, [t.name for t in robot.trajectories], str(output))
    with atomic_output(output, overwrite) as temporary:
        temporary.write_text(text, encoding="utf-8")
    return DesignSummary(
        tuple(paths),
        budget_rules,
        seed,
        design,
        output,
        made_by,
        differing,
        repeats,
        time.perf_counter() - started,
    )
