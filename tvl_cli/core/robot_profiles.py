"""The robots tvl ships, by the name `--robot` takes, and how a robot is named in words.

A profile is a whole `RobotConfig`: body, trajectories and sonar ring. The paper's robot, the
Yamabico of its Figure 8, is every command's default. The small one is the size of a
TurtleBot3 Burger, for maps drawn for it, such as Nav2's TurtleBot3 sandbox: its body radius,
its top speed of 0.22 m/s on the straight, the paper's arcs scaled to its body, and a ring
that hears from 0.1 m to 3.5 m.
"""

from __future__ import annotations

from tvl_cli.core.robot_config import RobotConfig, SonarConfig, seven_trajectories

DEFAULT_ROBOT_NAME = "yamabico"  # the paper's robot (its Figure 8)
DEFAULT_ROBOT = RobotConfig()

TURTLEBOT3_NAME = "turtlebot3"
TURTLEBOT3 = RobotConfig(
    radius_m=0.105,
    trajectories=seven_trajectories(radii_m=(0.25, 0.5, 1.0), v_max_mps=(0.15, 0.18, 0.20, 0.22)),
    # A smaller ring's transducers, close to the body, hear nearer and not so far.
    sonar=SonarConfig(min_range_m=0.10, max_range_m=3.5),
)

ROBOT_PROFILES: dict[str, RobotConfig] = {
    DEFAULT_ROBOT_NAME: DEFAULT_ROBOT,
    TURTLEBOT3_NAME: TURTLEBOT3,
}


def body_of(robot: RobotConfig) -> RobotConfig:
    """The robot apart from the model its ring is heard by (`--sonar`, the method's choice):
    what a FAM's velocities belong to."""
    return robot.heard_by("real")


def profile_name(robot: RobotConfig) -> str | None:
    """The profile a robot is, whatever its sonar model; None for a robot of its own."""
    body = body_of(robot)
    return next((name for name, profile in ROBOT_PROFILES.items() if profile == body), None)


def robot_name(robot: RobotConfig) -> str:
    """The profile a robot is (whatever its sonar model), or its size for one of its own."""
    named = profile_name(robot)
    if named is not None:
        return f"the {named} robot"
    return f"a robot of its own ({2 * robot.radius_m:g} m across)"
