"""A Nav2 user's map in one command: a map_server map made here (its frame off the image, as
Nav2's are) goes import -> learn -> train -> run with no option but the map, and everything
after the import speaks the map's frame: the world, the run's poses and goal, the replay, and
the MCAP, where Foxglove finds the map and the robot in one frame."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import invoke
from map_samples import FREE, OCCUPIED, ROS1_FREE_THRESH, UNKNOWN, write_map
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

from tvl_cli.io.runfile import read_run
from tvl_cli.sim.worldmap import load_world

# Each command here runs for a second or more (in this process, but for the last two tests).
pytestmark = pytest.mark.slow

RESOLUTION_M = 0.05
ORIGIN = (-10.0, -6.0)  # the image's bottom-left corner in the map's frame


def warehouse_pixels() -> np.ndarray:
    """A 6 x 5 m hall at 5 cm with a column and a shelf in it, unknown all round, as SLAM
    leaves it."""
    pixels = np.full((120, 140), UNKNOWN, dtype=np.uint8)
    pixels[10:112, 10:132] = OCCUPIED
    pixels[11:111, 11:131] = FREE
    pixels[30:40, 90:100] = OCCUPIED  # a column 0.5 m square
    pixels[80:84, 25:65] = OCCUPIED  # a shelf 2 m long
    return pixels


@pytest.fixture(scope="module")
def pipeline(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The map imported, learnt in (15 simulated minutes), trained on and run in (5 minutes
    of avoiding), each with no option but the files."""
    where = tmp_path_factory.mktemp("nav2")
    origin = "[{:g}, {:g}, 0]".format(*ORIGIN)
    map_yaml = write_map(
        where, warehouse_pixels(), free_thresh=ROS1_FREE_THRESH, name="hall", origin=origin
    )
    files = {name: where / name for name in ("hall.txt", "log.h5", "fam.h5", "run.h5")}
    for args in (
        ("world", "import", map_yaml, "-o", files["hall.txt"]),
        ("learn", files["hall.txt"], "--log", files["log.h5"]),
        ("train", files["log.h5"], "-o", files["fam.h5"]),
        ("run", files["fam.h5"], files["hall.txt"], "--behaviour", "avoid", "--log",
         files["run.h5"]),
        ("export", files["run.h5"], "--mcap", where / "run.mcap"),
    ):  # fmt: skip
        done = invoke(*args)
        assert done.returncode == 0, (args, done.stderr)
    return {**files, "map": map_yaml, "mcap": where / "run.mcap"}


def test_the_world_lies_where_the_map_does(pipeline) -> None:
    world = load_world(pipeline["hall.txt"])
    # The hall's walls' outer box: image columns 10..131, rows 10..111 (from the top).
    assert world.origin_m == (ORIGIN[0] + 10 * RESOLUTION_M, ORIGIN[1] + 8 * RESOLUTION_M)
    assert (world.width_m, world.height_m) == (6.1, 5.1)  # 122 x 102 cells
    x, y, _ = world.start
    assert -9.45 < x < -3.45 and -5.55 < y < -0.55  # on the hall's floor


def test_the_run_drove_on_the_maps_free_floor(pipeline) -> None:
    trace = read_run(pipeline["run.h5"])
    poses = trace.arrays["pose"]
    assert np.hypot(*np.diff(poses[:, :2], axis=0).T).sum() > 20.0  # it went about
    columns = np.floor((poses[:, 0] - ORIGIN[0]) / RESOLUTION_M).astype(int)
    rows = 120 - 1 - np.floor((poses[:, 1] - ORIGIN[1]) / RESOLUTION_M).astype(int)
    assert (warehouse_pixels()[rows, columns] == FREE).all()


def test_the_mcap_holds_the_map_and_the_robot_in_one_frame(pipeline) -> None:
    with pipeline["mcap"].open("rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        found = {}
        for _, channel, _, message in reader.iter_decoded_messages(["/map", "/tf"]):
            found.setdefault(channel.topic, message)
    grid, transform = found["/map"], found["/tf"]
    assert grid.frame_id == transform.parent_frame_id == "map"
    assert transform.child_frame_id == "base_link"
    world = load_world(pipeline["hall.txt"])
    assert (grid.pose.position.x, grid.pose.position.y) == world.origin_m
    # The robot's first pose, on a free cell of the grid it is drawn over.
    column = int((transform.translation.x - grid.pose.position.x) / grid.cell_size.x)
    row = int((transform.translation.y - grid.pose.position.y) / grid.cell_size.y)
    assert grid.data[row * grid.row_stride + column] == 0


def test_a_goal_is_given_in_the_maps_frame(pipeline, run_tvl) -> None:
    goal = "-4,-1"  # the hall's far corner, clear of the column
    done = run_tvl(
        "run", pipeline["fam.h5"], pipeline["hall.txt"], "--behaviour", "goal", "--goal", goal,
        "--minutes", "0.2", "--json",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    outside = run_tvl(
        "run", pipeline["fam.h5"], pipeline["hall.txt"], "--behaviour", "goal", "--goal", "1,1",
    )  # fmt: skip
    assert outside.returncode == 2
    assert "goal x 1 y 1 is outside the world (the map is -9.5..-3.4 x -5.6..-0.5 m)" in (
        outside.stderr
    )


def test_the_replay_speaks_the_maps_frame(pipeline, run_tvl) -> None:
    done = run_tvl("replay", pipeline["run.h5"], "--json")
    assert done.returncode == 0, done.stderr
    replay = json.loads(done.stdout)
    assert replay["steps"] == read_run(pipeline["run.h5"]).steps
