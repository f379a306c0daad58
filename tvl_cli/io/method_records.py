"""The method a file was made by, read back whole from any version of it.

Files of the current versions (log 2, FAM 3, run trace 4) keep the method once: their
`method` attribute, every field of it (core.method.method_record). Older files kept its
pieces where each was first needed: the labels in a FAM's training provenance or a log
session's parameters, the echo memory in a FAM's `memory` attribute or a session's
parameters, the collision points and the exploration rule in a session's parameters, the
sonar in the robot, the reflexes in a trace's parameters; later ones a `method` attribute of
some fields beside them. This module is the one place that reads those pieces: each reader
here returns a whole Method, with the fields the file did not record (filled with ours)
named, so that a file never read as made by a method it was not made by without saying so.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

from tvl_cli.core.errors import BadInput
from tvl_cli.core.labels import BUMP_LABELS, TOP_SPEED_CEILING
from tvl_cli.core.memory import NO_MEMORY, MemoryConfig
from tvl_cli.core.method import (
    FIELDS,
    LEARNING_FIELDS,
    LEAST_EXPERIENCE,
    SESSIONS_DIFFER_IN,
    Method,
    method_from_dict,
    method_record,
)
from tvl_cli.core.robot_config import RobotConfig, sonar_model_name


@dataclass(frozen=True, slots=True)
class ReadMethod:
    """A file's method, the fields it did not record (filled with ours), and those in which
    the sessions it was made from differ (the first's are recorded)."""

    method: Method
    unrecorded: tuple[str, ...] = ()
    mixed: tuple[str, ...] = ()

    def record(self) -> dict[str, Any]:
        """As --json and the files made from it record it (core.method.method_record)."""
        return method_record(self.method, unrecorded=self.unrecorded, mixed=self.mixed)


def _from_record(
    record: Mapping[str, Any] | None,
    pieces: Mapping[str, Any],
    where: str,
    relevant: tuple[str, ...] = FIELDS,
) -> ReadMethod:
    """The recorded fields, then the older pieces for the fields the record lacks, then ours
    for what neither gives; of the `relevant` fields (those that made the file), those
    neither gave are unrecorded."""
    given = {k: v for k, v in (record or {}).items() if k in FIELDS}
    values = {**pieces, **given}
    method = method_from_dict(values, f"{where} method")
    return ReadMethod(method, tuple(n for n in relevant if n not in values))


def current(record: Any, where: str, mixed: Any = ()) -> ReadMethod:
    """The method of a file of the current version: its record, which must be there; with the
    fields its sources differ in (a FAM's provenance names them)."""
    if not isinstance(record, dict):
        raise BadInput(f"{where} method: not recorded")
    return replace(_from_record(record, _UNCEILED, where), mixed=_fields(mixed, where))


def _fields(names: Any, where: str) -> tuple[str, ...]:
    if not isinstance(names, list | tuple) or not all(n in FIELDS for n in names):
        raise BadInput(f"{where}: {SESSIONS_DIFFER_IN} is not a list of the method's fields")
    return tuple(names)


# What every file that does not record its labels' ceiling was made by: labels no faster than
# the top speed, the only ones there were.
_UNCEILED = {"label_ceiling": TOP_SPEED_CEILING, "label_ceiling_radius_m": None}
# What every file older than its method's record was made by, recorded or not: labels of the
# driven trajectory alone (the heard labels came with the record), capped at the top speed.
_OLDER = {"labels": BUMP_LABELS, **_UNCEILED}


def _memory(value: Any, where: str) -> dict[str, Any]:
    try:
        return MemoryConfig.from_dict(value or {}).to_dict()
    except BadInput as error:
        raise BadInput(f"{where}: {error}") from None


def _sonar(robot: RobotConfig) -> dict[str, Any]:
    name = sonar_model_name(robot.sonar)
    return {} if name is None else {"sonar": name}


def _numbers(source: Mapping[str, Any], keys: tuple[str, ...]) -> dict[str, Any]:
    return {k: source[k] for k in keys if k in source}


def session_method(
    record: Any, parameters: Mapping[str, Any], robot: RobotConfig, where: str
) -> ReadMethod:
    """A log session's method: its record; for a session of log version 1, the record of its
    learning fields (where it has one) over what its parameters and robot say."""
    pieces: dict[str, Any] = {
        **_OLDER,
        **_numbers(parameters, ("decel_mps2", "margin_m", "near_m")),
        # Sessions written before there was a choice explored by the paper's rule, and
        # through no memory.
        "exploration": parameters.get("explore", LEAST_EXPERIENCE),
        "memory": _memory(parameters.get("memory"), where),
        **_sonar(robot),
    }
    return _from_record(
        record if isinstance(record, dict) else None, pieces, where, LEARNING_FIELDS
    )


def fam_method(
    record: Any,
    memory: Any,
    provenance: Mapping[str, Any],
    robot: RobotConfig,
    where: str,
) -> ReadMethod:
    """A FAM's method: its record; for a FAM of version 1 or 2, the record of its learning
    fields (where it has one) over its labels (provenance), its memory attribute (none where
    it has none: a version 1 FAM reads the live ring) and its robot's sonar."""
    training = provenance.get("training")
    pieces: dict[str, Any] = {
        **_OLDER,
        **_numbers(training if isinstance(training, dict) else {}, ("decel_mps2", "margin_m")),
        "memory": _memory(memory, where) if memory is not None else NO_MEMORY.to_dict(),
        **_sonar(robot),
    }
    record = record if isinstance(record, dict) else None
    read = _from_record(record, pieces, where, LEARNING_FIELDS)
    return replace(read, mixed=_fields((record or {}).get(SESSIONS_DIFFER_IN, []), where))


def trace_method(
    record: Any, parameters: Mapping[str, Any], robot: RobotConfig, where: str
) -> ReadMethod:
    """A run trace's method: its record; for a trace of version 3 or older, its record (where
    it has one) over the reflexes, memory and sonar its parameters and robot say."""
    pieces: dict[str, Any] = {**_OLDER, **_sonar(robot)}
    if "reflexes" in parameters:
        pieces["reflexes"] = parameters["reflexes"]
    if "memory" in parameters:
        pieces["memory"] = _memory(parameters["memory"], where)
    return _from_record(record if isinstance(record, dict) else None, pieces, where)
