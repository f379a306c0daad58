"""What a sweep's workers do, each call whole or not at all: learn a log, train a FAM, and a
cell's own work, which comes back as its row's measures."""

from __future__ import annotations

from dataclasses import asdict, replace
from pathlib import Path

from tvl_cli.commands.baseline import dwa_session, qlearn_session
from tvl_cli.commands.learn import learn_to_log
from tvl_cli.commands.replay import LogReplay, replay
from tvl_cli.commands.run import run_behaviour
from tvl_cli.commands.train import train_from_logs, write_trained
from tvl_cli.core.errors import BadInput
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.loglayout import STATUS_FINISHED
from tvl_cli.io.table import Row
from tvl_cli.sweep.cell import DWA, LEARN, TVL
from tvl_cli.sweep.layout import CellWork, LogRequest, TrainRequest, given


def do_cell(work: CellWork) -> Row:
    """A cell's own work, and what it found as the verb's --json prints it: a learn cell's
    log as `tvl replay` sums it up, a TVL run as `tvl run`, a baseline as `tvl baseline`."""
    if work.kind == LEARN:
        assert work.log is not None
        return _learnt(work.log)
    if work.kind == TVL:
        assert work.run is not None and work.root is not None
        found = run_behaviour(work.run).to_dict()
        if work.run.trace is not None:
            found["trace_file"] = work.run.trace.relative_to(work.root).as_posix()
        return found
    assert work.baseline is not None
    world, cell, method = work.baseline
    if work.kind == DWA:
        report = dwa_session(
            world,
            given(cell.behaviour),
            cell.goal_xy(),
            given(cell.run_minutes),
            cell.seed,
            method=method,
        )
        return asdict(report.metrics)
    return qlearn_session(
        world,
        given(cell.learn_minutes),
        given(cell.run_minutes),
        cell.seed,
        cell.competence_every or None,  # 0: no checks
        method=method,
    ).to_dict()


def _learnt(log: Path) -> Row:
    """A learning log's session and its minutes, as `tvl replay --json` gives them."""
    summary = replay(log)
    assert isinstance(summary, LogReplay)  # the sweep's logs are learning logs
    (session,) = summary.sessions  # the sweep learns each log in one session
    return {
        "episodes": session.episodes,
        "collisions": session.collisions,
        "exemplars": session.exemplars,
        "sim_minutes": session.sim_minutes,
        "coverage": session.coverage,
        "minutes": summary.minutes,
    }


def learn_log(request: LogRequest) -> None:
    """Learn a new log whole at its path, or leave no file there; BadInput naming the grid's
    learn_minutes when the learning finished no episode, which leaves nothing to train."""
    learn = request.learn
    with atomic_output(learn.log) as temporary:
        # learn_to_log makes the log itself (or adds to one that exists): it learns under the
        # name atomic_output reserved, renamed into place only once learning has finished.
        temporary.unlink()
        result = learn_to_log(replace(learn, log=temporary))
        if result.status != STATUS_FINISHED:
            raise KeyboardInterrupt  # a signal stopped the learning: it stops the sweep too
        if result.summary.episodes == 0:
            raise BadInput(
                f"{request.minutes_key}: learning in world {learn.world_name!r} (seed "
                f"{learn.seed}) finished no episode, so there is nothing to train; give "
                "more learn_minutes"
            )


def train_fam(request: TrainRequest) -> None:
    """Train a FAM from a log (as it stood at a minute) by a method, as `tvl train LOG -o FAM
    --method [--until-minute]` does."""
    trained = train_from_logs(
        [request.log], request.config, request.method, until_minute=request.until_minute
    )
    write_trained(request.fam, trained)
