"""A FAM configuration by name (`single`, `multi`, `designed`) or from a JSON file of the
user's own (`--config`)."""

from __future__ import annotations

from pathlib import Path

from tvl_cli.core.errors import BadInput, did_you_mean
from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS, FamConfig
from tvl_cli.core.fam_config_json import fam_config_from_json
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.text import decoded


def resolve_fam_config(spec: str, robot: RobotConfig) -> FamConfig:
    """`single`, `multi`, or a JSON file of the user's own."""
    if spec in BUILTIN_FAM_CONFIGS:
        return BUILTIN_FAM_CONFIGS[spec]
    path = Path(spec)
    if not path.is_file():
        raise BadInput(
            f"{spec}: no such FAM configuration, nor a JSON file "
            f"({did_you_mean(spec, list(BUILTIN_FAM_CONFIGS))})"
        )
    try:
        data = path.read_bytes()
    except OSError as error:
        raise BadInput(f"{spec}: cannot read the FAM configuration ({error.strerror})") from None
    text = decoded(data, spec)
    return fam_config_from_json(text, [t.name for t in robot.trajectories], spec)
