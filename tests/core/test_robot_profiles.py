"""The shipped robots, the sonar models heard on any robot's ring, and a robot named in words."""

from __future__ import annotations

from dataclasses import replace

import pytest

from tvl_cli.core.robot_config import (
    SONAR_MODEL_NAMES,
    SONAR_MODELS,
    RobotConfig,
    SonarConfig,
    Trajectory,
    sonar_model,
    sonar_model_name,
)
from tvl_cli.core.robot_profiles import (
    DEFAULT_ROBOT,
    ROBOT_PROFILES,
    TURTLEBOT3,
    body_of,
    profile_name,
    robot_name,
)


def test_the_papers_trajectories_are_those_of_its_figure_8() -> None:
    assert RobotConfig().trajectories == (
        Trajectory("T3L", 2.0, 0.35),
        Trajectory("T2L", 1.0, 0.45),
        Trajectory("T1L", 0.5, 0.55),
        Trajectory("T0", 0.0, 0.60),
        Trajectory("T1R", -0.5, 0.55),
        Trajectory("T2R", -1.0, 0.45),
        Trajectory("T3R", -2.0, 0.35),
    )


def test_the_turtlebot3_is_a_burger_with_arcs_scaled_to_its_body() -> None:
    assert TURTLEBOT3.radius_m == 0.105
    assert [t.radius_m for t in TURTLEBOT3.trajectories[:3]] == [0.25, 0.5, 1.0]
    assert max(TURTLEBOT3.v_max_mps) == 0.22  # a Burger's top speed
    assert (TURTLEBOT3.sonar.min_range_m, TURTLEBOT3.sonar.max_range_m) == (0.10, 3.5)
    # The ring and the choice rule take seven trajectories, mirrored about the straight one.
    names = [t.name for t in TURTLEBOT3.trajectories]
    assert names == [t.name for t in DEFAULT_ROBOT.trajectories]
    assert [t.curvature_per_m for t in TURTLEBOT3.trajectories] == [
        4.0,
        2.0,
        1.0,
        0.0,
        -1.0,
        -2.0,
        -4.0,
    ]


def test_the_sonar_models_on_the_papers_ring_are_as_they_always_were() -> None:
    assert {
        "real": SonarConfig(),
        "edges": SonarConfig(edge_echo_range_m=1.0),
        "ideal": SonarConfig(ideal=True),
    } == SONAR_MODELS


@pytest.mark.parametrize("profile", sorted(ROBOT_PROFILES))
@pytest.mark.parametrize("model", SONAR_MODEL_NAMES)
def test_every_robots_ring_is_heard_by_every_model_and_named_back(profile: str, model: str) -> None:
    ring = ROBOT_PROFILES[profile].sonar
    heard = sonar_model(ring, model)
    assert sonar_model_name(heard) == model
    assert heard.max_range_m == ring.max_range_m and heard.min_range_m == ring.min_range_m
    assert sonar_model(heard, "real") == ring  # each model goes back to the ring as built


def test_the_edges_model_hears_a_quarter_of_the_rings_range() -> None:
    assert sonar_model(TURTLEBOT3.sonar, "edges").edge_echo_range_m == 3.5 / 4


def test_a_ring_heard_another_way_has_no_models_name() -> None:
    assert sonar_model_name(SonarConfig(edge_echo_range_m=0.3)) is None


def test_a_robot_is_named_by_its_profile_whatever_its_sonar_model() -> None:
    ideal = replace(TURTLEBOT3, sonar=sonar_model(TURTLEBOT3.sonar, "ideal"))
    assert body_of(ideal) == TURTLEBOT3
    assert robot_name(ideal) == "the turtlebot3 robot"
    assert robot_name(DEFAULT_ROBOT) == "the yamabico robot"
    assert robot_name(RobotConfig(radius_m=0.3)) == "a robot of its own (0.6 m across)"
    assert profile_name(ideal) == "turtlebot3" and profile_name(RobotConfig(radius_m=0.3)) is None
