"""Robot files (`--robot FILE.toml`): changes to a shipped profile, every fault one line naming
the file and the key."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from tvl_cli.core.errors import BadInput
from tvl_cli.core.robot_config import seven_trajectories
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT, TURTLEBOT3
from tvl_cli.io import robotfile
from tvl_cli.io.robotfile import read_robot, resolve_robot
from tvl_cli.io.tomlfile import loads_toml


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "bot.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_the_documented_example_reads_as_it_says(tmp_path: Path) -> None:
    doc = str(robotfile.__doc__)
    example = doc[doc.index("# A robot") : doc.index("\nEvery key")]  # the module's example
    robot = read_robot(write(tmp_path, example))
    assert robot == replace(
        TURTLEBOT3,
        radius_m=0.14,
        trajectories=seven_trajectories((0.3, 0.6, 1.2), (0.15, 0.18, 0.2, 0.22)),
        sonar=replace(TURTLEBOT3.sonar, min_range_m=0.1, max_range_m=3.5, cone_deg=25.0),
    )


def test_what_a_file_does_not_give_is_its_bases(tmp_path: Path) -> None:
    assert read_robot(write(tmp_path, "radius_m = 0.25\n")) == replace(DEFAULT_ROBOT, radius_m=0.25)
    speeds = read_robot(write(tmp_path, "[trajectories]\nv_max_mps = [0.1, 0.2, 0.3, 0.4]\n"))
    assert [t.radius_m for t in speeds.trajectories[:3]] == [0.5, 1.0, 2.0]  # the paper's arcs
    assert speeds.v_max_mps == (0.1, 0.2, 0.3, 0.4, 0.3, 0.2, 0.1)


def test_robots_are_named_by_profile_or_file(tmp_path: Path) -> None:
    assert resolve_robot("turtlebot3") is TURTLEBOT3
    assert resolve_robot("yamabico") is DEFAULT_ROBOT
    assert resolve_robot(write(tmp_path, "base = 'turtlebot3'\n")) == TURTLEBOT3
    with pytest.raises(BadInput) as refused:
        resolve_robot("turtlebot")
    assert str(refused.value) == (
        "--robot turtlebot: neither a robot (yamabico, turtlebot3) nor a robot file "
        "(did you mean 'turtlebot3'?)"
    )


@pytest.mark.parametrize(
    "text, error",
    [
        ("radius = 0.2\n", "unknown key radius (did you mean 'radius_m'?)"),
        ("base = 'burger'\n", "base 'burger': choose yamabico, turtlebot3"),
        ("radius_m = '0.2'\n", "radius_m '0.2' must be a number"),
        ("radius_m = true\n", "radius_m True must be a number"),
        ("radius_m = nan\n", "radius_m nan must be 0.03 or more and at most 1 m"),
        ("radius_m = 5.0\n", "radius_m 5 must be 0.03 or more and at most 1 m"),
        ("trajectories = 1\n", "trajectories must be a table ([trajectories])"),
        ("[trajectories]\nradii = [1]\n",
         "unknown key trajectories.radii (did you mean 'radii_m'?)"),
        ("[trajectories]\nradii_m = [1, 2]\n", "trajectories.radii_m must be a list of 3 numbers"),
        ("[trajectories]\nradii_m = [2, 1, 3]\n",
         "trajectories.radii_m [2.0, 1.0, 3.0]: list the arcs tightest first"),
        ("[trajectories]\nv_max_mps = [0.1, 0.2, 0.3, inf]\n",
         "trajectories.v_max_mps inf must be 0.01 or more and at most 3 m/s"),
        ("[sonar]\ncount = 8\n", "unknown key sonar.count (known: min_range_m, max_range_m, "
         "cone_deg, specular_max_deg, noise_sigma_m, noise_fraction)"),
        ("[sonar]\nmin_range_m = 5.0\n",
         "sonar.min_range_m 5 must be below sonar.max_range_m 4"),
        ("[sonar]\ncone_deg = 1e308\n", "sonar.cone_deg 1e+308 must be 1 or more and at most 90 °"),
    ],
)  # fmt: skip
def test_a_fault_is_one_line_naming_the_file_and_the_key(
    tmp_path: Path, text: str, error: str
) -> None:
    path = write(tmp_path, text)
    with pytest.raises(BadInput) as refused:
        read_robot(path)
    assert str(refused.value) == f"{path}: {error}"


def test_a_file_nested_too_deep_is_one_line(tmp_path: Path) -> None:
    path = write(tmp_path, "radius_m = " + "[" * 5000 + "]" * 5000 + "\n")
    with pytest.raises(BadInput) as refused:
        read_robot(path)
    assert str(refused.value).startswith(f"{path}:1: ")


def test_the_robot_guides_example_file_reads() -> None:
    guide = (Path(__file__).resolve().parents[2] / "docs" / "guide" / "robot.md").read_text()
    example = guide.split("```toml\n", 1)[1].split("```", 1)[0]
    robot = robotfile.robot_from_table(loads_toml(example, "robot.md"), "robot.md")
    assert robot.radius_m == 0.14 and robot.sonar == TURTLEBOT3.sonar
