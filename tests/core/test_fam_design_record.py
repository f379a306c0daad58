"""The record of how a configuration was chosen from data: optional, round-tripped, checked."""

from __future__ import annotations

import json
from dataclasses import replace
from typing import Any

import pytest

from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import MULTI, SINGLE, FamConfig, FamDesign, InputChoice
from tvl_cli.core.fam_config_json import fam_config_from_json
from tvl_cli.core.robot_config import RobotConfig

NAMES = [t.name for t in RobotConfig().trajectories]
RECORDED = replace(
    SINGLE,
    design=FamDesign(
        seed=7,
        budget_rules=720,
        logs_sha256=("ab" * 32,),
        choices=(InputChoice("all", ("front", "front-left"), 0.16, 0.04),),
    ),
)


def document(**changes: Any) -> dict[str, Any]:
    data = json.loads(RECORDED.to_json())
    data["design"].update(changes)
    return data


def test_a_configuration_without_a_design_writes_no_design_key() -> None:
    for config in (SINGLE, MULTI):
        assert "design" not in config.to_dict()
        assert FamConfig.from_dict(json.loads(config.to_json())) == config


def test_a_design_round_trips_through_json() -> None:
    read = fam_config_from_json(RECORDED.to_json(), NAMES)
    assert read == RECORDED
    assert read.design is not None and read.design.choices[0].heldout_error_after_mps == 0.04


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"seed": -1}, "'seed' is -1, expected a whole number"),
        ({"budget_rules": 1.5}, "'budget_rules' is 1.5, expected a whole number"),
        ({"logs_sha256": [3]}, "'logs_sha256' holds 3, expected text"),
        ({"why": "guess"}, "unknown key 'why'"),
        (
            {"choices": [{"table": "all", "inputs": ["front"], "heldout_error_before_mps": -1}]},
            "'heldout_error_before_mps' is -1, expected a speed",
        ),
        (
            {
                "choices": [
                    {
                        "table": "T0",
                        "inputs": [],
                        "heldout_error_before_mps": 0.1,
                        "heldout_error_after_mps": 0.05,
                    }
                ]
            },
            "design choice 0: no table 'T0'",
        ),
        (
            {
                "choices": [
                    {
                        "table": "all",
                        "inputs": ["S3"],
                        "heldout_error_before_mps": 0.1,
                        "heldout_error_after_mps": 0.05,
                    }
                ]
            },
            "table 'all' has no input 'S3'",
        ),
    ],
)
def test_a_bad_design_record_is_refused_by_name(changes: dict[str, Any], message: str) -> None:
    with pytest.raises(BadInput, match=message):
        fam_config_from_json(json.dumps(document(**changes)), NAMES, "mine.json")


def test_a_design_missing_a_key_names_it() -> None:
    data = document()
    del data["design"]["choices"]
    with pytest.raises(BadInput, match=r"mine\.json: missing key 'choices'"):
        fam_config_from_json(json.dumps(data), NAMES, "mine.json")
