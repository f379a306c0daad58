"""tvl: Trajectory Velocity Learning for a simulated sonar-ring mobile robot."""

__version__ = "0.1.0"
