"""`tvl train`: rebuild a FAM from learning logs alone (log replay)."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.core.config import FamConfig, RobotConfig
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.training import TrainParams, train_episode
from tvl_cli.io.logreader import LearningLog, read_log


@dataclass(frozen=True, slots=True)
class TrainSummary:
    fam: Fam
    robot: RobotConfig
    provenance: dict[str, Any]
    exemplars: int
    episodes: int
    rules_touched: int
    rules_total: int
    wall_s: float


def common_robot(logs: Sequence[LearningLog]) -> RobotConfig:
    """The one robot configuration of every session; BadInput naming the first that differs."""
    first = logs[0].sessions[0].robot_config
    for log in logs:
        for session in log.sessions:
            if session.robot_config != first:
                raise BadInput(
                    f"{log.path}: session {session.name} was recorded with another robot "
                    f"configuration than {logs[0].path} session {logs[0].sessions[0].name}; "
                    "logs of different robots cannot train one FAM"
                )
    return first


def _refuse_repeated(logs: Sequence[LearningLog]) -> None:
    """The same log given twice would train every exemplar twice."""
    seen: dict[str, Path] = {}
    for log in logs:
        if log.sha256 in seen:
            raise BadInput(f"{log.path}: the same log as {seen[log.sha256]}, given twice")
        seen[log.sha256] = log.path


def provenance(logs: Sequence[LearningLog], params: TrainParams, config: FamConfig) -> dict:
    """Everything needed to rebuild the FAM: its sources and every training parameter."""
    return {
        "logs": [
            {
                "path": str(log.path),
                "sha256": log.sha256,
                "sessions": [
                    {
                        "name": s.name,
                        "world": s.world_name,
                        "seed": s.seed,
                        "status": s.status,
                        "episodes": len(s.episode_table),
                        "exemplars": s.exemplar_count,
                    }
                    for s in log.sessions
                ],
            }
            for log in logs
        ],
        "training": {"config": config.name, **params.to_dict()},
    }


def train_from_logs(
    paths: Sequence[Path],
    config: FamConfig,
    params: TrainParams,
    on_progress: Callable[[int, int], None] = lambda done, total: None,
    until_minute: float | None = None,
) -> TrainSummary:
    """Train a new FAM on every episode of every log, in log, session and episode order;
    with `until_minute`, only on the episodes each session finished by then (a snapshot of
    what the learner knew at that minute)."""
    started = time.perf_counter()
    if until_minute is not None and not (math.isfinite(until_minute) and until_minute >= 0):
        raise BadInput(f"--until-minute {until_minute:g} must be a number of minutes >= 0")
    logs = [read_log(path) for path in paths]
    _refuse_repeated(logs)
    robot = common_robot(logs)
    fam = Fam(config, [t.name for t in robot.trajectories], params.init_velocity_mps)
    episodes = [e for log in logs for s in log.sessions for e in s.episodes()]
    if until_minute is not None:
        episodes = [e for e in episodes if e.end_time_s <= until_minute * 60.0]
    total = sum(e.exemplar_count for e in episodes)
    done = 0
    for episode in episodes:
        train_episode(fam, episode, robot, params)
        done += episode.exemplar_count
        on_progress(done, total)
    tables = range(len(config.tables))
    touched = sum(int(np.count_nonzero(fam.experience_table(t).sum(axis=1))) for t in tables)
    return TrainSummary(
        fam=fam,
        robot=robot,
        provenance={**provenance(logs, params, config), "until_minute": until_minute},
        exemplars=total,
        episodes=len(episodes),
        rules_touched=touched,
        rules_total=config.rule_count,
        wall_s=time.perf_counter() - started,
    )
