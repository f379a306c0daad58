"""The FAM file (`tvl-fam`): learnt velocities and experience, with how they were learnt.

Layout (format_version 3):

    /                 format, format_version, tvl_version, created, config (FamConfig JSON),
                      robot_config (JSON), init_velocity_mps, trajectories, method (JSON,
                      core.method.method_record: every choice of the method it was made by,
                      its labels and the echo memory it reads through among them),
                      provenance (JSON: the logs and sessions it was trained from, and the
                      training settings that are not the method's)
    /fams/<table>     one group per FAM table, e.g. /fams/all or /fams/T1L
        velocity      table.shape + (trajectories,) float64 m/s, one axis per input
        experience    the same shape, unitless (summed rule firing strengths, eq. 1)
        axes/<input>  the input's fuzzy-set centres (m), set names in `set_names`: the
                      dimension scale of that input's axis
        axes/trajectory  the table's trajectory names: the scale of the last axis

Versions 1 and 2 kept the method's pieces (its labels in the provenance's training, the
memory in a `memory` attribute from version 2, some fields in an optional `method`);
io.method_records reads them.

Datasets are written with fixed settings, so the same FAM always gives the same dataset
bytes; only the `created` attribute tells two writes apart.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import FamConfig, FamTable
from tvl_cli.core.labels import trajectory_ceilings
from tvl_cli.core.method import SESSIONS_DIFFER_IN, Method, method_record
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.hdf5_header import (
    FAM_FORMAT,
    METHOD_RECORDED_SINCE,
    FormatError,
    hdf5_output,
    open_for_reading,
    read_json_attr,
    read_str_attr,
    write_header,
)
from tvl_cli.io.method_records import ReadMethod, current, fam_method

FAMS = "fams"
AXES = "axes"
TRAJECTORY_AXIS = "trajectory"
_COMPRESSION: dict[str, Any] = {"compression": "gzip", "compression_opts": 4, "shuffle": True}


@dataclass(frozen=True, slots=True, eq=False)
class FamFile:
    """A FAM file as read back: the FAM, the robot it is for, and how it was made."""

    fam: Fam
    robot_config: RobotConfig
    provenance: dict[str, Any]
    tvl_version: str
    created: str  # UTC ISO 8601
    made_by: ReadMethod  # the method it was made by: its labels, and the memory it reads

    @property
    def method(self) -> Method:
        return self.made_by.method


def write_fam(
    path: Path | str,
    fam: Fam,
    *,
    robot_config: RobotConfig,
    method: Method,
    provenance: dict[str, Any],
    overwrite: bool = True,
) -> None:
    """Write `fam`, made by `method`, to `path` atomically: a failure leaves any existing file
    untouched, and without `overwrite` a file that appeared meanwhile is refused, not
    replaced."""
    names = tuple(t.name for t in robot_config.trajectories)
    if fam.trajectory_names != names:
        raise ValueError(f"FAM trajectories {fam.trajectory_names} are not the robot's {names}")
    check_storable(fam.config)
    with hdf5_output(path, overwrite) as f:
        write_header(
            f,
            FAM_FORMAT,
            config=fam.config.to_dict(),
            robot_config=robot_config.to_dict(),
            method=method_record(method),
            provenance=provenance,
        )
        f.attrs["init_velocity_mps"] = fam.init_velocity_mps
        f.attrs["trajectories"] = list(names)
        fams = f.create_group(FAMS)
        for t, table in enumerate(fam.config.tables):
            _write_table(fams.create_group(table.name), table, fam, t)


def check_storable(config: FamConfig, source: str = "FAM configuration") -> None:
    """BadInput naming `source` (the configuration's file) unless a FAM of `config` can be
    written: its names become HDF5 names."""
    for table in config.tables:
        _check_hdf5_name(table.name, "table", source)
        for fam_input in table.inputs:
            _check_hdf5_name(fam_input.name, "input", source)


def _check_hdf5_name(name: str, what: str, source: str) -> None:
    """Table and input names become HDF5 names, which cannot hold '/' or be '.'."""
    if "/" in name or name in ("", ".") or (what == "input" and name == TRAJECTORY_AXIS):
        raise BadInput(f"{source}: {what} name {name!r} cannot be stored in a FAM file")


def _write_table(group: h5py.Group, table: FamTable, fam: Fam, t: int) -> None:
    group.attrs["trajectories"] = list(table.trajectories)
    group.attrs["inputs"] = [i.name for i in table.inputs]
    group.attrs["rule_count"] = table.rule_count
    axes = group.create_group(AXES)
    scales = []
    for fam_input in table.inputs:
        scale = axes.create_dataset(
            fam_input.name, data=np.array(fam_input.partition.centres_m, dtype="<f8")
        )
        scale.attrs.update(
            units="m",
            set_names=list(fam_input.partition.names),
            sonars=np.array(fam_input.sonars, dtype="<i4"),
            description=f"fuzzy-set centres of input {fam_input.name}",
        )
        scale.make_scale(fam_input.name)
        scales.append((fam_input.name, scale))
    trajectory = axes.create_dataset(
        TRAJECTORY_AXIS, data=np.array(table.trajectories, dtype=h5py.string_dtype())
    )
    trajectory.make_scale(TRAJECTORY_AXIS)
    scales.append((TRAJECTORY_AXIS, trajectory))

    shape = (*table.shape, len(table.trajectories))  # one axis per input, then trajectories
    tables = {
        "velocity": (fam.velocity_table(t), "m/s", "learnt velocity of each rule (eq. 2)"),
        "experience": (
            fam.experience_table(t),
            "1",
            "experience of each rule: summed firing strengths of its exemplars (eq. 1)",
        ),
    }
    for name, (values, units, description) in tables.items():
        dataset = group.create_dataset(
            name, data=values.reshape(shape), dtype="<f8", chunks=True, **_COMPRESSION
        )
        dataset.attrs.update(units=units, description=description)
        for axis, (label, scale) in enumerate(scales):
            dataset.dims[axis].attach_scale(scale)
            dataset.dims[axis].label = label


def read_fam(path: Path | str) -> FamFile:
    """Read a FAM file; FormatError naming the file if it is not a readable tvl-fam."""
    path = Path(path)
    with open_for_reading(path, FAM_FORMAT) as f:
        try:
            return _read(f, path)
        except BadInput as error:
            if isinstance(error, FormatError):
                raise
            raise FormatError(f"{path}: {error}") from None
        except (OSError, KeyError, ValueError, TypeError) as error:
            raise FormatError(f"{path}: corrupt tvl-fam ({error})") from None


_ROUNDING_MPS = 1e-9  # an average of labels at a maximum may round a few ulps above it


def _read(f: h5py.File, path: Path) -> FamFile:
    config = FamConfig.from_dict(read_json_attr(f, "config", path))
    robot = RobotConfig.from_dict(read_json_attr(f, "robot_config", path))
    provenance = read_json_attr(f, "provenance", path)
    made_by = _method(f, path, provenance, robot)
    method = made_by.method
    # A learnt velocity is an average of labels, each between 0 and the trajectory's maximum
    # times its labels' ceiling (give or take the rounding of the average): anything else
    # was not learnt.
    top_labels = np.array(robot.v_max_mps) * trajectory_ceilings(
        robot.radii_m, method.label_ceiling, method.label_ceiling_radius_m
    )
    velocities: list[np.ndarray] = []  # per table (rules, trajectories) m/s
    experience: list[np.ndarray] = []
    for table in config.tables:
        group = f[f"{FAMS}/{table.name}"]
        shape = (*table.shape, len(table.trajectories))
        rows = (table.rule_count, len(table.trajectories))
        for name, arrays in (("velocity", velocities), ("experience", experience)):
            values = group[name][()]
            if values.shape != shape:
                raise FormatError(
                    f"{path}: {group.name}/{name} has shape {values.shape}, "
                    f"the configuration says {shape}"
                )
            if values.dtype.kind != "f":
                raise FormatError(f"{path}: {group.name}/{name} holds {values.dtype}, not floats")
            arrays.append(values.reshape(rows))
        top = top_labels[[robot.trajectory_index(n) for n in table.trajectories]]
        if not ((velocities[-1] >= 0) & (velocities[-1] <= top + _ROUNDING_MPS)).all():
            raise FormatError(
                f"{path}: {group.name}/velocity holds speeds outside 0 to each trajectory's "
                "maximum (times the labels' ceiling)"
            )
    fam = Fam.from_tables(
        config,
        [t.name for t in robot.trajectories],
        velocities,
        experience,
        float(f.attrs["init_velocity_mps"]),
    )
    return FamFile(
        fam=fam,
        robot_config=robot,
        provenance=provenance,
        tvl_version=read_str_attr(f, "tvl_version", path),
        created=read_str_attr(f, "created", path),
        made_by=made_by,
    )


def _method(f: h5py.File, path: Path, provenance: Any, robot: RobotConfig) -> ReadMethod:
    """The FAM's method, from its record or, in a file of version 1 or 2, its pieces."""
    optional = {n: read_json_attr(f, n, path) for n in ("method", "memory") if n in f.attrs}
    where = "FAM"  # read_fam names the file
    if not isinstance(provenance, dict):
        raise FormatError(f"{path}: provenance is not a JSON object")
    if int(f.attrs["format_version"]) >= METHOD_RECORDED_SINCE[FAM_FORMAT]:
        return current(optional.get("method"), where, provenance.get(SESSIONS_DIFFER_IN, []))
    return fam_method(optional.get("method"), optional.get("memory"), provenance, robot, where)
