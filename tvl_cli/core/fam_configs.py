"""FAM configurations from users: parsed from JSON and checked before any FAM is built."""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any

import numpy as np

from tvl_cli.core.config import SONAR_COUNT, FamConfig, Partition
from tvl_cli.core.errors import BadInput

MAX_INPUTS_PER_TABLE = 10  # 2^10 rules fire per reading; more makes inference crawl
MAX_ENTRIES = 20_000_000  # rules x trajectories in all: 3 float64 arrays that size, 480 MB


def validate_fam_config(
    config: FamConfig, trajectory_names: Sequence[str], source: str = "FAM configuration"
) -> None:
    """Raise BadInput naming `source` and the first problem that makes `config` unusable."""
    known = set(trajectory_names)
    covered: dict[str, str] = {}
    if not config.tables:
        raise BadInput(f"{source}: no tables")
    if len({t.name for t in config.tables}) != len(config.tables):
        raise BadInput(f"{source}: table names are not unique")
    for table in config.tables:
        where = f"{source}: table {table.name!r}"
        if not table.inputs:
            raise BadInput(f"{where}: no inputs")
        if len(table.inputs) > MAX_INPUTS_PER_TABLE:
            raise BadInput(f"{where}: {len(table.inputs)} inputs, at most {MAX_INPUTS_PER_TABLE}")
        if len({i.name for i in table.inputs}) != len(table.inputs):
            raise BadInput(f"{where}: input names are not unique")
        for fam_input in table.inputs:
            _validate_input(fam_input.name, fam_input.sonars, fam_input.partition, where)
        if not table.trajectories:
            raise BadInput(f"{where}: no trajectories")
        for name in table.trajectories:
            if name not in known:
                choices = ", ".join(trajectory_names)
                raise BadInput(f"{where}: unknown trajectory {name!r} (choose from {choices})")
            if name in covered:
                raise BadInput(
                    f"{where}: trajectory {name!r} is already stored by table {covered[name]!r}"
                )
            covered[name] = table.name
    missing = [n for n in trajectory_names if n not in covered]
    if missing:
        raise BadInput(f"{source}: no table stores trajectory {', '.join(missing)}")
    entries = sum(t.rule_count * len(t.trajectories) for t in config.tables)
    if entries > MAX_ENTRIES:
        raise BadInput(f"{source}: {entries:,} rule entries, at most {MAX_ENTRIES:,}")


def _validate_input(name: str, sonars: tuple[int, ...], partition: Partition, where: str) -> None:
    where = f"{where} input {name!r}"
    if not sonars:
        raise BadInput(f"{where}: no sonars")
    for s in sonars:
        if not 0 <= s < SONAR_COUNT:
            raise BadInput(f"{where}: sonar {s} is outside 0..{SONAR_COUNT - 1}")
    if len(set(partition.names)) != len(partition.names):
        raise BadInput(f"{where}: fuzzy-set names are not unique")
    if not all(np.isfinite(partition.centres_m)):
        raise BadInput(f"{where}: fuzzy-set centres must be finite")


def fam_config_from_json(
    text: str, trajectory_names: Sequence[str], source: str = "FAM configuration"
) -> FamConfig:
    """Parse and validate a user's FAM configuration; BadInput naming `source` if unusable."""
    try:
        data = json.loads(text)
    except json.JSONDecodeError as error:
        raise BadInput(f"{source}:{error.lineno}:{error.colno}: not JSON: {error.msg}") from None
    except RecursionError:
        raise BadInput(f"{source}: JSON nested too deeply for a FAM configuration") from None
    if not isinstance(data, dict):
        raise BadInput(f"{source}: expected a JSON object with 'name' and 'tables'")
    _check_schema(data, source)
    try:
        config = FamConfig.from_dict(data)
    except KeyError as error:
        raise BadInput(f"{source}: missing key {error}") from None
    except (TypeError, ValueError, AttributeError) as error:
        raise BadInput(f"{source}: {error}") from None
    validate_fam_config(config, trajectory_names, source)
    return config


# The keys of each level of a FAM configuration; any other is a typo, named rather than ignored.
_CONFIG_KEYS = ("name", "tables")
_TABLE_KEYS = ("name", "inputs", "trajectories")
_INPUT_KEYS = ("name", "sonars", "partition")
_PARTITION_KEYS = ("names", "centres_m")


def _check_schema(data: dict[str, Any], source: str) -> None:
    """Unknown keys and sonars that are not whole numbers, before anything is converted."""
    _known_keys(data, _CONFIG_KEYS, source)
    tables = data.get("tables")
    for t, table in enumerate(tables if isinstance(tables, list) else []):
        where = f"{source}: table {t}"
        if not isinstance(table, dict):
            raise BadInput(f"{where}: expected an object with {', '.join(_TABLE_KEYS)}")
        _known_keys(table, _TABLE_KEYS, where)
        inputs = table.get("inputs")
        for i, fam_input in enumerate(inputs if isinstance(inputs, list) else []):
            at = f"{where} input {i}"
            if not isinstance(fam_input, dict):
                raise BadInput(f"{at}: expected an object with {', '.join(_INPUT_KEYS)}")
            _known_keys(fam_input, _INPUT_KEYS, at)
            if isinstance(fam_input.get("partition"), dict):
                _known_keys(fam_input["partition"], _PARTITION_KEYS, f"{at} partition")
            sonars = fam_input.get("sonars")
            for sonar in sonars if isinstance(sonars, list) else []:
                if isinstance(sonar, bool) or not isinstance(sonar, int):
                    raise BadInput(f"{at}: sonar {sonar!r} is not a whole number")


def _known_keys(data: dict[str, Any], allowed: tuple[str, ...], where: str) -> None:
    unknown = [key for key in data if key not in allowed]
    if unknown:
        raise BadInput(f"{where}: unknown key {unknown[0]!r} (expected {', '.join(allowed)})")
