"""The run trace (`tvl-run`): every control step of one behaviour run, and its metrics.

Layout:

    /             format, format_version, tvl_version, created, world_name, world_text,
                  parameters (JSON: behaviour, threshold, minutes, goal, seed, FAM file and
                  its SHA-256), robot_config (JSON), metrics (JSON: what `tvl run --json` prints)
    pose          (N, 3) float64  true x, y (m), theta (rad) after each step
    odometry      (N, 3) float64  odometry x, y (m), theta (rad) after each step
    ring_mm       (N, 16) uint16  sonar ranges read before the step, mm
    velocities    (N, 7) float64  perceived m/s of the 7 trajectories facing forward
    trajectory    (N,) int8       trajectory driven, -1 while spinning, reversing or trapped
    speed_mps     (N,) float64    commanded forward speed (negative when reversing)
    bumped        (N,) bool       bump sensor after the step
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.logfile import ring_to_mm
from tvl_cli.io.schema import (
    LIBVER,
    RUN_FORMAT,
    FormatError,
    open_for_reading,
    read_json_attr,
    read_str_attr,
    write_header,
)

_COMPRESSION: dict[str, Any] = {"compression": "gzip", "compression_opts": 4, "shuffle": True}
# name -> (units, description)
_DATASETS: dict[str, tuple[str, str]] = {
    "pose": ("m, m, rad", "true pose x, y, theta after each control step"),
    "odometry": ("m, m, rad", "odometry pose x, y, theta after each control step"),
    "ring_mm": ("mm", "sonar ranges S0..S15 read before the step, S0 forward, CCW"),
    "velocities": ("m/s", "perceived velocity of each trajectory, facing forward"),
    "trajectory": ("", "trajectory driven (robot_config order); -1 spinning or reversing"),
    "speed_mps": ("m/s", "commanded forward speed, negative when reversing"),
    "bumped": ("", "bump sensor after the step"),
}


@dataclass(frozen=True, slots=True, eq=False)
class RunTrace:
    """A run as recorded step by step."""

    world_name: str
    world_text: str
    parameters: dict[str, Any]
    metrics: dict[str, Any]
    arrays: dict[str, np.ndarray]  # the datasets above, by name

    @property
    def steps(self) -> int:
        return len(self.arrays["pose"])


def write_run(
    path: Path | str,
    *,
    world_name: str,
    world_text: str,
    parameters: dict[str, Any],
    robot_config: dict[str, Any],
    metrics: dict[str, Any],
    steps: dict[str, list[Any]],
) -> None:
    """Write a whole run trace atomically; `steps` holds one list per dataset name."""
    arrays = {
        "pose": np.array(steps["pose"], dtype=np.float64).reshape(-1, 3),
        "odometry": np.array(steps["odometry"], dtype=np.float64).reshape(-1, 3),
        "ring_mm": ring_to_mm(np.array(steps["ring_m"], dtype=np.float64).reshape(-1, 16)),
        "velocities": np.array(steps["velocities"], dtype=np.float64).reshape(-1, 7),
        "trajectory": np.array(steps["trajectory"], dtype=np.int8),
        "speed_mps": np.array(steps["speed_mps"], dtype=np.float64),
        "bumped": np.array(steps["bumped"], dtype=bool),
    }
    with atomic_output(path) as temporary, h5py.File(temporary, "w", libver=LIBVER) as f:
        write_header(
            f, RUN_FORMAT, parameters=parameters, robot_config=robot_config, metrics=metrics
        )
        f.attrs.update(world_name=world_name, world_text=world_text)
        for name, values in arrays.items():
            units, description = _DATASETS[name]
            chunked = _COMPRESSION if len(values) else {}
            dataset = f.create_dataset(name, data=values, **chunked)
            dataset.attrs.update(units=units, description=description)


def read_run(path: Path | str) -> RunTrace:
    """Read a run trace; FormatError if it is not a readable tvl-run file."""
    with open_for_reading(path, RUN_FORMAT) as f:
        missing = [name for name in _DATASETS if name not in f]
        if missing:
            raise FormatError(f"{path}: run trace has no {', '.join(missing)} dataset")
        try:
            arrays = {name: f[name][()] for name in _DATASETS}
        except OSError as error:
            raise FormatError(f"{path}: run trace is corrupt ({error})") from None
        return RunTrace(
            world_name=read_str_attr(f, "world_name", path),
            world_text=read_str_attr(f, "world_text", path),
            parameters=read_json_attr(f, "parameters", path),
            metrics=read_json_attr(f, "metrics", path),
            arrays=arrays,
        )
