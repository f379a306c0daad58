"""`tvl export --mcap`: a run trace read back with the mcap library holds Foxglove's schemas,
a message a step on each channel, the trace's poses, ring, velocities and events, and the
world's walls; bad inputs are one line."""

from __future__ import annotations

import json
import math
import shutil
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner
from json_schemas import valid
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

from tvl_cli.cli.main import main
from tvl_cli.core.contacts import EVENTS
from tvl_cli.io.runfile import RunTrace, read_run
from tvl_cli.sim.worldmap import parse_world

ROOT = Path(__file__).resolve().parents[2]
LAB = ROOT / "worlds" / "lab.txt"
PER_STEP = ("/tf", "/pose", "/odometry", "/sonar", "/perceived")
SCHEMAS = {
    "/map": ("foxglove.Grid", "protobuf"),
    "/world": ("foxglove.SceneUpdate", "protobuf"),
    "/tf": ("foxglove.FrameTransform", "protobuf"),
    "/pose": ("foxglove.PoseInFrame", "protobuf"),
    "/odometry": ("foxglove.PoseInFrame", "protobuf"),
    "/sonar": ("foxglove.PointCloud", "protobuf"),
    "/perceived": ("tvl.PerceivedVelocities", "json"),
    "/events": ("foxglove.Log", "protobuf"),
}


def tvl(*args: object) -> tuple[int, str, str]:
    done = CliRunner().invoke(main, [str(a) for a in args])
    return done.exit_code, done.stdout, done.stderr


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Half a simulated minute of avoiding in the lab, with a FAM from the example log."""
    directory = tmp_path_factory.mktemp("run")
    fam, trace = directory / "fam.h5", directory / "run.h5"
    assert tvl("train", ROOT / "logs" / "square-s1.h5", "-o", fam)[0] == 0
    code, _, stderr = tvl(
        "run", fam, LAB, "--behaviour", "avoid", "--minutes", "0.5", "--log", trace
    )
    assert code == 0, stderr
    return trace


@pytest.fixture(scope="module")
def exported(run: Path) -> Path:
    out = run.with_name("run.mcap")
    code, _, stderr = tvl("export", run, "--mcap", out)
    assert code == 0, stderr
    return out


def messages(path: Path, topic: str) -> list[tuple[int, Any]]:
    """(log time ns, decoded message) of a topic, in time order; JSON as a dict."""
    with path.open("rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        if topic == "/perceived":
            return [(m.log_time, json.loads(m.data)) for _, _, m in reader.iter_messages([topic])]
        return [(m.log_time, d) for _, _, m, d in reader.iter_decoded_messages([topic])]


def test_every_channel_has_its_foxglove_schema(exported: Path) -> None:
    with exported.open("rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None
    found = {
        c.topic: (summary.schemas[c.schema_id].name, c.message_encoding)
        for c in summary.channels.values()
    }
    assert found == SCHEMAS


def test_each_step_is_one_message_on_each_channel_and_the_world_one(
    exported: Path, run: Path
) -> None:
    trace = read_run(run)
    with exported.open("rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None and summary.statistics is not None
    counts = {
        summary.channels[i].topic: n for i, n in summary.statistics.channel_message_counts.items()
    }
    assert {topic: counts[topic] for topic in PER_STEP} == dict.fromkeys(PER_STEP, trace.steps)
    assert counts["/world"] == counts["/map"] == 1
    began = sum(len(trace.event_steps(event)) for event in EVENTS)
    assert began > 0 and counts["/events"] == began


def _yaw(q: Any) -> float:
    return 2.0 * math.atan2(q.z, q.w)


def test_the_first_and_last_poses_are_the_traces(exported: Path, run: Path) -> None:
    trace = read_run(run)
    for topic, name in (("/pose", "pose"), ("/odometry", "odometry")):
        found = messages(exported, topic)
        for (time_ns, message), step in ((found[0], 0), (found[-1], trace.steps - 1)):
            x, y, theta = trace.arrays[name][step]
            pose = message.pose
            assert (pose.position.x, pose.position.y) == (x, y)
            assert math.isclose(math.cos(_yaw(pose.orientation) - theta), 1.0)
            assert time_ns == round((step + 1) * trace.period_s * 1e9)
            assert message.frame_id == "map"


def test_the_map_is_the_worlds_cells_in_the_map_frame(exported: Path, run: Path) -> None:
    world = parse_world(read_run(run).world_text, "lab")
    ((time_ns, grid),) = messages(exported, "/map")
    assert time_ns == 0 and grid.frame_id == "map"
    assert (grid.pose.position.x, grid.pose.position.y) == world.origin_m
    assert (grid.cell_size.x, grid.cell_size.y) == (world.cell_m, world.cell_m)
    rows = len(grid.data) // grid.row_stride
    cells = np.frombuffer(grid.data, dtype=np.int8).reshape(rows, grid.column_count)
    assert (rows * world.cell_m, grid.column_count * world.cell_m) == (
        world.height_m,
        world.width_m,
    )
    # Row 0 is the bottom row: the lab's bottom wall, then the floor above it.
    assert (cells[0] == 100).all() and set(np.unique(cells)) == {0, 100}
    assert (cells[1:-1, 1:-1] == 0).mean() > 0.5


def test_the_world_scene_holds_every_wall_and_disc(exported: Path, run: Path) -> None:
    world = parse_world(read_run(run).world_text, "lab")
    ((time_ns, update),) = messages(exported, "/world")
    scene = {entity.id: entity for entity in update.entities}
    walls = scene["world"].lines[0]
    assert time_ns == 0 and len(walls.points) == 2 * len(world.segments)
    ends = [(p.x, p.y) for p in walls.points]
    assert ends[:2] == [world.segments[0][:2], world.segments[0][2:]]
    assert len(scene["world"].cylinders) == len(world.discs) > 0
    assert scene["robot"].frame_locked and scene["robot"].frame_id == "base_link"


def test_the_sonar_points_are_the_rings_echoes_read_at_the_steps_start(
    exported: Path, run: Path
) -> None:
    trace = read_run(run)
    found = messages(exported, "/sonar")
    step = int(np.flatnonzero(trace.arrays["ring_mm"].any(axis=1))[0])
    time_ns, cloud = found[step]
    assert time_ns == round(step * trace.period_s * 1e9) and cloud.frame_id == "base_link"
    fields = {f.name: f.offset for f in cloud.fields}
    assert list(fields) == ["x", "y", "z", "range_m", "sonar", "echo"]
    points = np.frombuffer(
        cloud.data,
        dtype=np.dtype(
            {
                "names": list(fields),
                "formats": ["<f4"] * 4 + ["u1"] * 2,
                "offsets": list(fields.values()),
                "itemsize": cloud.point_stride,
            }
        ),
    )
    ring_m = trace.arrays["ring_mm"][step] / 1000.0
    assert np.allclose(points["range_m"], ring_m) and points["sonar"].tolist() == list(range(16))
    bearing = 2 * np.pi * np.arange(16) / 16
    reach = trace.robot_config["radius_m"] + ring_m
    assert np.allclose(points["x"], reach * np.cos(bearing), atol=1e-5)
    assert np.allclose(points["y"], reach * np.sin(bearing), atol=1e-5)


def test_the_perceived_velocities_are_the_traces_by_trajectory_name(
    exported: Path, run: Path
) -> None:
    trace = read_run(run)
    names = [t["name"] for t in trace.robot_config["trajectories"]]
    found = messages(exported, "/perceived")
    for step in (0, trace.steps // 2, trace.steps - 1):
        _, message = found[step]
        velocities = trace.arrays["velocities"][step]
        assert message["velocities_mps"] == {
            name: None if math.isnan(v) else v for name, v in zip(names, velocities, strict=True)
        }
        driven = int(trace.arrays["trajectory"][step])
        assert message["driven"] == (names[driven] if driven >= 0 else None)


def test_the_events_are_logged_at_the_end_of_the_steps_that_began_them(
    exported: Path, run: Path
) -> None:
    trace = read_run(run)
    logged = Counter((time_ns, log.message) for time_ns, log in messages(exported, "/events"))
    expected = Counter(
        (round((int(step) + 1) * trace.period_s * 1e9), event)
        for event in EVENTS
        for step in trace.event_steps(event)
    )
    assert logged == expected


def test_the_same_trace_exports_to_the_same_bytes(exported: Path, run: Path) -> None:
    again = run.with_name("again.mcap")
    assert tvl("export", run, "--mcap", again)[0] == 0
    assert again.read_bytes() == exported.read_bytes()


def test_an_existing_output_is_kept_unless_force(run: Path, tmp_path: Path) -> None:
    out = tmp_path / "out.mcap"
    out.write_text("keep me")
    code, _, stderr = tvl("export", run, "--mcap", out)
    assert code == 2 and "out.mcap: already exists (use --force to overwrite)" in stderr
    assert out.read_text() == "keep me"
    code, stdout, _ = tvl("export", run, "--mcap", out, "--force", "--json")
    assert code == 0
    messages = {m["topic"]: m["messages"] for m in valid("export", stdout)["messages"]}
    assert messages["/world"] == 1
    assert out.read_bytes().startswith(b"\x89MCAP0\r\n")


def test_a_learning_log_is_refused_in_one_line(tmp_path: Path) -> None:
    log = ROOT / "logs" / "square-s1.h5"
    code, _, stderr = tvl("export", log, "--mcap", tmp_path / "out.mcap")
    assert code == 2 and stderr.splitlines() == [
        f"tvl: error: {log}: is a learning log; tvl export writes run traces (tvl run --log RUN.h5)"
    ]
    assert not (tmp_path / "out.mcap").exists()


@pytest.mark.parametrize(
    ("content", "message"),
    [(b"", "is empty, not an HDF5 file"), (b"not hdf5 at all", "not an HDF5 file")],
)
def test_a_file_that_is_no_trace_is_one_line(content: bytes, message: str, tmp_path: Path) -> None:
    bad = tmp_path / "bad.h5"
    bad.write_bytes(content)
    code, _, stderr = tvl("export", bad, "--mcap", tmp_path / "out.mcap")
    assert code == 2 and stderr.splitlines() == [f"tvl: error: {bad}: {message}"]
    assert not (tmp_path / "out.mcap").exists()


def test_the_output_may_not_be_the_trace(run: Path, tmp_path: Path) -> None:
    # An output named as an MCAP, and a trace named so too: the one file, given as both.
    named = tmp_path / "run.mcap"
    shutil.copy(run, named)
    code, _, stderr = tvl("export", named, "--mcap", named, "--force")
    assert code == 2 and "given as both --mcap and RUN.h5" in stderr
    assert isinstance(read_run(named), RunTrace)
    code, _, stderr = tvl("export", run, "--mcap", run, "--force")
    assert code == 2 and "it is written as MCAP; give it the extension .mcap" in stderr
    assert isinstance(read_run(run), RunTrace)


@pytest.mark.parametrize(
    ("attribute", "value", "message"),
    [
        ("metrics", "{}", "run trace's metrics give no simulated time (sim_s)"),
        ("robot_config", '{"radius_m": -1}', "run trace's robot_config is malformed"),
    ],
)
def test_a_trace_without_a_clock_or_a_robot_is_one_line(
    attribute: str, value: str, message: str, run: Path, tmp_path: Path
) -> None:
    import shutil

    import h5py

    broken = tmp_path / "broken.h5"
    shutil.copy(run, broken)
    with h5py.File(broken, "r+") as f:
        f.attrs[attribute] = value
    code, _, stderr = tvl("export", broken, "--mcap", tmp_path / "out.mcap")
    (line,) = stderr.splitlines()
    assert code == 2 and line.startswith(f"tvl: error: {broken}: {message}")
    assert not (tmp_path / "out.mcap").exists()


def test_a_trace_of_no_steps_is_refused_and_nothing_is_written(run: Path, tmp_path: Path) -> None:
    import shutil

    import h5py

    empty = tmp_path / "empty.h5"
    shutil.copy(run, empty)
    with h5py.File(empty, "r+") as f:  # every step's dataset cut to none
        for dataset in f.values():
            if isinstance(dataset, h5py.Dataset):
                dataset.resize(0, axis=0)
    assert read_run(empty).steps == 0
    out = tmp_path / "out.mcap"
    code, _, stderr = tvl("export", empty, "--mcap", out)
    assert code == 2 and stderr.splitlines() == [
        f"tvl: error: {empty}: the run trace has no steps: nothing to export"
    ]
    assert not out.exists()
    out.write_text("keep me")
    assert tvl("export", empty, "--mcap", out, "--force")[0] == 2
    assert out.read_text() == "keep me"
