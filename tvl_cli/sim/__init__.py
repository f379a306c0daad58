"""The simulated world: pymunk bodies, the sonar ring, the robot, batches of robots, maps."""

__all__ = [
    "batch",
    "bodies",
    "canvas",
    "clearance_kernel",
    "flood_kernel",
    "geometry",
    "maps",
    "motion",
    "ring_kernel",
    "robot",
    "rooms",
    "sonar",
    "true_arcs",
    "wall_grid",
    "world_budget",
    "world_entries",
    "worldgen",
    "worldheader",
    "worldmap",
]
