"""The suites' options as the command line gives them, checked into requests: BadInput naming
the option at the first fault, before anything runs."""

from __future__ import annotations

from pathlib import Path

from tvl_cli.bench.controllers import parse_controller
from tvl_cli.bench.generalization_suite import GeneralizationRequest
from tvl_cli.bench.references import REFERENCES
from tvl_cli.core.behaviours import is_threshold
from tvl_cli.core.errors import BadInput, did_you_mean
from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.fam_config_file import resolve_fam_config
from tvl_cli.io.logreader import read_log
from tvl_cli.io.methodfile import resolve_method


def generalization_request(
    world_set: str,
    span: str | None,
    trials: int | None,
    method: str,
    configs: tuple[str, ...],
    controllers: tuple[str, ...],
    observe: str | None,
    references: str,
    threshold: float,
    size: str,
    pool: tuple[str, ...] = (),
) -> GeneralizationRequest:
    if not is_threshold(threshold):
        raise BadInput(f"--threshold {threshold:g} is outside (0, 1]")
    chosen = configs or tuple(BUILTIN_FAM_CONFIGS)
    if len(set(chosen)) < len(chosen):
        raise BadInput("--config: a configuration is given twice")
    resolved = tuple(resolve_fam_config(spec, RobotConfig()) for spec in chosen)
    if len({c.name for c in resolved}) < len(resolved):
        raise BadInput("--config: two configurations share a name; rows know them by it")
    return GeneralizationRequest(
        method=resolve_method(method, label="--method"),
        method_name=method,
        world_set=world_set,
        span=None if span is None else parse_span(span),
        trials=trials,
        size=size,
        configs=resolved,
        controllers=tuple(parse_controller(text) for text in controllers),
        observe=None if observe is None else resolve_method(observe, label="--observe"),
        references=parse_references(references),
        threshold=threshold,
        pool=pooled_logs(pool),
    )


def pooled_logs(paths: tuple[str, ...]) -> tuple[tuple[str, str], ...]:
    """--pool's logs, each as (absolute path, SHA-256), read as `tvl train` reads a log: a
    file that is not a learning log is refused here, before anything runs."""
    if len(set(paths)) < len(paths):
        raise BadInput("--pool: a log is given twice")
    pooled = []
    for text in paths:
        log = read_log(Path(text))
        pooled.append((str(Path(text).resolve()), log.sha256))
    return tuple(pooled)


def parse_span(text: str) -> tuple[int, int]:
    """`N` (the first N worlds) or `A-B` (the A-th to B-th, from 1)."""
    first, dash, last = text.partition("-")
    if not dash:
        first, last = "1", text
    if not (first.isdigit() and last.isdigit()) or not 1 <= int(first) <= int(last):
        raise BadInput(f"--worlds {text}: give N or A-B, worlds counted from 1, A before B")
    return int(first), int(last)


def parse_references(text: str) -> tuple[str, ...]:
    """`all`, `none` or names, in the order of REFERENCES."""
    if text == "all":
        return tuple(REFERENCES)
    if text == "none":
        return ()
    names = [name.strip() for name in text.split(",")]
    for name in names:
        if name not in REFERENCES:
            raise BadInput(
                f"--references {text}: no reference {name!r} "
                f"({did_you_mean(name, list(REFERENCES))})"
            )
    return tuple(name for name in REFERENCES if name in names)
