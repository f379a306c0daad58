"""Driving the robot: the step engine, the drive loop, the TVL policy, reflexes, learning."""

__all__ = [
    "collision_points",
    "drive",
    "drive_tvl",
    "engine",
    "explore",
    "explore_rules",
    "memory_kernel",
    "motions",
    "novelty",
    "online",
    "perception",
    "policy",
    "recording",
    "reflexes",
    "trace",
    "true_velocities",
    "tvl",
]
