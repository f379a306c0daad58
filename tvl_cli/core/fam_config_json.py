"""FAM configurations from users: parsed from JSON and checked before any FAM is built."""

from __future__ import annotations

import json
import math
from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np

from tvl_cli.core import jsontext
from tvl_cli.core.errors import BadInput, did_you_mean
from tvl_cli.core.fam_config import FamConfig, Partition
from tvl_cli.core.robot_config import SONAR_COUNT, SonarConfig

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
    _validate_design(config, source)
    entries = sum(t.rule_count * len(t.trajectories) for t in config.tables)
    if entries > MAX_ENTRIES:
        raise BadInput(f"{source}: {entries:,} rule entries, at most {MAX_ENTRIES:,}")


def _validate_design(config: FamConfig, source: str) -> None:
    """A design's choices name the tables and inputs they chose, so that a reader can trust
    the record it describes this configuration."""
    if config.design is None:
        return
    inputs = {t.name: {i.name for i in t.inputs} for t in config.tables}
    for c, choice in enumerate(config.design.choices):
        where = f"{source}: design choice {c}"
        if choice.table not in inputs:
            raise BadInput(f"{where}: no table {choice.table!r}")
        for name in choice.inputs:
            if name not in inputs[choice.table]:
                raise BadInput(f"{where}: table {choice.table!r} has no input {name!r}")


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
        data = jsontext.loads(
            text,
            source,
            object_pairs_hook=lambda pairs: _unique_keys(pairs, source),
        )
    except json.JSONDecodeError as error:
        raise BadInput(f"{source}:{error.lineno}:{error.colno}: not JSON: {error.msg}") from None
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
_CONFIG_KEYS = ("name", "tables", "design")
_DESIGN_KEYS = ("seed", "budget_rules", "logs_sha256", "choices")
_CHOICE_KEYS = ("table", "inputs", "heldout_error_before_mps", "heldout_error_after_mps")
_TABLE_KEYS = ("name", "inputs", "trajectories")
_INPUT_KEYS = ("name", "sonars", "partition")
_PARTITION_KEYS = ("names", "centres_m")


# A reading is at most the sonar's range, so a fuzzy set centred beyond it (or below 0 m) is
# one no reading could ever be in the middle of.
MAX_CENTRE_M = SonarConfig().max_range_m


def _check_schema(data: dict[str, Any], source: str) -> None:
    """Unknown keys, names that are not text, sonars that are not whole numbers and centres
    outside the sonar's range, before anything is converted (which would make 5 into "5")."""
    _known_keys(data, _CONFIG_KEYS, source)
    _text(data, "name", source)
    if "design" in data:
        _check_design(data["design"], f"{source}: design")
    for where, table in _objects(data.get("tables"), _TABLE_KEYS, f"{source}: table"):
        _text(table, "name", where)
        _texts(table, "trajectories", where)
        for at, fam_input in _objects(table.get("inputs"), _INPUT_KEYS, f"{where} input"):
            _text(fam_input, "name", at)
            if isinstance(fam_input.get("partition"), dict):
                _check_partition(fam_input["partition"], f"{at} partition")
            sonars = fam_input.get("sonars")
            for sonar in sonars if isinstance(sonars, list) else []:
                if isinstance(sonar, bool) or not isinstance(sonar, int):
                    raise BadInput(f"{at}: sonar {sonar!r} is not a whole number")


def _objects(items: Any, keys: tuple[str, ...], where: str) -> Iterator[tuple[str, dict[str, Any]]]:
    """Each item of a list, numbered after `where`, checked to be an object of no other keys
    than `keys` (a value that is not a list has no items: its own check names it)."""
    for n, item in enumerate(items if isinstance(items, list) else []):
        at = f"{where} {n}"
        if not isinstance(item, dict):
            raise BadInput(f"{at}: expected an object with {', '.join(keys)}")
        _known_keys(item, keys, at)
        yield at, item


def _check_design(design: Any, where: str) -> None:
    """The record of `tvl design`: whole numbers, texts and errors in m/s as it writes them."""
    if not isinstance(design, dict):
        raise BadInput(f"{where}: expected an object with {', '.join(_DESIGN_KEYS)}")
    _known_keys(design, _DESIGN_KEYS, where)
    for key in ("seed", "budget_rules"):
        value = design.get(key, 0)  # a missing key is named when the record is built
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            raise BadInput(f"{where}: {key!r} is {value!r}, expected a whole number >= 0")
    _texts(design, "logs_sha256", where)
    for at, choice in _objects(design.get("choices"), _CHOICE_KEYS, f"{where} choice"):
        _text(choice, "table", at)
        _texts(choice, "inputs", at)
        for key in _CHOICE_KEYS[2:]:
            value = choice.get(key, 0.0)
            number = isinstance(value, int | float) and not isinstance(value, bool)
            if not (number and math.isfinite(value) and value >= 0):
                raise BadInput(f"{at}: {key!r} is {value!r}, expected a speed >= 0 m/s")


def _check_partition(partition: dict[str, Any], where: str) -> None:
    _known_keys(partition, _PARTITION_KEYS, where)
    _texts(partition, "names", where)
    centres = partition.get("centres_m")
    for centre in centres if isinstance(centres, list) else []:
        number = isinstance(centre, int | float) and not isinstance(centre, bool)
        if not (number and 0 <= centre <= MAX_CENTRE_M):
            raise BadInput(
                f"{where}: centre {centre!r} is outside the sonar's range, 0 to {MAX_CENTRE_M:g} m"
            )


def _known_keys(data: dict[str, Any], allowed: tuple[str, ...], where: str) -> None:
    unknown = [key for key in data if key not in allowed]
    if unknown:
        raise BadInput(f"{where}: unknown key {unknown[0]!r} ({did_you_mean(unknown[0], allowed)})")


def _text(data: dict[str, Any], key: str, where: str) -> None:
    if key in data and not isinstance(data[key], str):
        raise BadInput(f"{where}: {key!r} is {data[key]!r}, expected text")


def _texts(data: dict[str, Any], key: str, where: str) -> None:
    values = data.get(key)
    for value in values if isinstance(values, list) else []:
        if not isinstance(value, str):
            raise BadInput(f"{where}: {key!r} holds {value!r}, expected text")


def _unique_keys(pairs: list[tuple[str, Any]], source: str) -> dict[str, Any]:
    """A JSON object's keys and values; BadInput on a key given twice (json keeps the last,
    so the first would be ignored without a word)."""
    data: dict[str, Any] = {}
    for key, value in pairs:
        if key in data:
            raise BadInput(f"{source}: the key {key!r} appears twice in one object")
        data[key] = value
    return data
