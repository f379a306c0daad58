"""The worlds guide quotes the limits of world files and map imports as the code has them."""

from __future__ import annotations

from doc_pages import page, section

from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.occupancy_map import MAX_YAML_BYTES, MAX_YAML_DEPTH
from tvl_cli.sim.world_budget import (
    BYTES_PER_CELL,
    BYTES_PER_IMAGE_PIXEL,
    BYTES_PER_SEGMENT,
    MAX_SEGMENTS,
    MEMORY_SHARE,
    MEMORY_VARIABLE,
)
from tvl_cli.sim.worldheader import MAX_HEADING_DEG, MAX_ORIGIN_M

WORLDS = page("guide/worlds.md")
FRAME = " ".join(section(WORLDS, "A map's frame and the start").split())
MAPS = " ".join(section(WORLDS, "Occupancy grids: ROS map_server and Nav2 maps").split())


def test_the_origin_and_the_starts_heading_are_quoted_with_their_ranges() -> None:
    assert f"each from −{MAX_ORIGIN_M:,.0f} to {MAX_ORIGIN_M:,.0f}" in FRAME
    assert f"from −{MAX_HEADING_DEG:g} to {MAX_HEADING_DEG:g}" in FRAME


def test_the_size_limits_are_quoted_as_they_are() -> None:
    assert MEMORY_SHARE == 0.5 and "more than half the memory of the machine" in MAPS
    assert f"`{MEMORY_VARIABLE}`" in MAPS
    assert f"about {BYTES_PER_CELL} bytes a cell and {BYTES_PER_SEGMENT:,} a wall segment" in MAPS
    assert f"at {BYTES_PER_IMAGE_PIXEL} bytes each" in MAPS
    assert f"more than {MAX_SEGMENTS:,} wall segments is refused" in MAPS


def test_the_yaml_limits_and_the_robots_size_are_quoted_as_they_are() -> None:
    assert f"at most {MAX_YAML_BYTES // 1024} kB" in MAPS
    assert f"nesting deeper than {MAX_YAML_DEPTH} levels" in MAPS
    radius = RobotConfig().radius_m
    assert f"narrower than the robot ({2 * radius:g} m across;" in MAPS
    assert f"footprint (π · {radius:g}² m²)" in MAPS
