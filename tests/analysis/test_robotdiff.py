"""How two robots differ, setting by setting: named sonar models by name, any other ring by
its settings, trajectories by their names."""

from __future__ import annotations

from dataclasses import replace

from tvl_cli.analysis.robotdiff import RobotDifference, robot_differences
from tvl_cli.core.robot_config import SONAR_MODELS, RobotConfig, Trajectory

ROBOT = RobotConfig()


def test_one_robot_differs_in_nothing() -> None:
    assert robot_differences(ROBOT, RobotConfig()) == []


def test_named_sonar_models_differ_by_name_alone() -> None:
    ideal = replace(ROBOT, sonar=SONAR_MODELS["ideal"])
    assert robot_differences(ROBOT, ideal) == [RobotDifference("sonar", "real", "ideal")]


def test_a_ring_of_no_model_differs_by_its_settings() -> None:
    longer = replace(ROBOT, sonar=replace(ROBOT.sonar, max_range_m=5.0))
    assert robot_differences(ROBOT, longer) == [RobotDifference("sonar.max_range_m", 4.0, 5.0)]


def test_trajectories_differ_by_name_and_setting() -> None:
    slower = tuple(
        Trajectory(t.name, t.curvature_per_m, 0.5) if t.name == "T1L" else t
        for t in ROBOT.trajectories
    )
    found = robot_differences(replace(ROBOT, radius_m=0.105), replace(ROBOT, trajectories=slower))
    assert [d.text() for d in found] == [
        "radius_m 0.105 → 0.2",
        "trajectories.T1L.v_max_mps 0.55 → 0.5",
    ]
