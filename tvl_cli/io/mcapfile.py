"""A run trace as an MCAP file, in Foxglove's well-known schemas, for Foxglove and other MCAP
tools to play back.

Channels, with a message for every step of the run unless said:

    /map        foxglove.Grid            once, at time 0: the world's cells as an occupancy grid
                                         in the map frame, its corner at the world's origin, one
                                         int8 `occupancy` a cell as ROS's OccupancyGrid has it
                                         (0 free, 100 occupied, -1 outside the world)
    /world      foxglove.SceneUpdate     once, at time 0: the walls as one line list, ring walls
                                         as line loops, discs and pillars as cylinders, and the
                                         robot's body, locked to base_link
    /tf         foxglove.FrameTransform  map -> base_link: the true pose
    /pose       foxglove.PoseInFrame     the true pose, in map
    /odometry   foxglove.PoseInFrame     the pose the wheels report, in map
    /sonar      foxglove.PointCloud      the ring's echo points in base_link, with each point's
                                         range_m, sonar (0 to 15) and echo (0 where the beam
                                         heard nothing and reads the maximum range); no points
                                         where the step read no ring
    /perceived  tvl.PerceivedVelocities  (JSON) the perceived velocities by trajectory name,
                                         m/s (null where none was perceived), and the
                                         trajectory driven
    /events     foxglove.Log             a message for each event a step began (bump, near
                                         miss, back-off, spin, trapped), level warning for
                                         contacts and traps

Every pose is in the `map` frame: the frame of the world, which is the frame of the map it was
imported from (`tvl world import`), so that a run lies over the map in Foxglove's 3D panel as
it lies in the world.

Time is simulated time from the run's start. A step's ring and perceived velocities are
stamped at its start, when the robot read and chose, where the step before left it; its pose,
odometry and events at its end ((i + 1) control periods for step i, the time `tvl replay` and
`tvl explain` give). So at any moment the ring drawn is the one read from the pose drawn. The
run's world, parameters and metrics are the file's `tvl-run` metadata.

Foxglove's schemas come compiled in protobuf from Foxglove's own package, so the file says
exactly what Foxglove reads; the perceived velocities have no well-known schema and travel as
JSON with a JSON Schema, which Foxglove reads as well.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from foxglove_schemas_protobuf.Color_pb2 import Color
from foxglove_schemas_protobuf.CylinderPrimitive_pb2 import CylinderPrimitive
from foxglove_schemas_protobuf.FrameTransform_pb2 import FrameTransform
from foxglove_schemas_protobuf.Grid_pb2 import Grid
from foxglove_schemas_protobuf.LinePrimitive_pb2 import LinePrimitive
from foxglove_schemas_protobuf.Log_pb2 import Log
from foxglove_schemas_protobuf.PackedElementField_pb2 import PackedElementField
from foxglove_schemas_protobuf.Point3_pb2 import Point3
from foxglove_schemas_protobuf.PointCloud_pb2 import PointCloud
from foxglove_schemas_protobuf.Pose_pb2 import Pose
from foxglove_schemas_protobuf.PoseInFrame_pb2 import PoseInFrame
from foxglove_schemas_protobuf.Quaternion_pb2 import Quaternion
from foxglove_schemas_protobuf.SceneEntity_pb2 import SceneEntity
from foxglove_schemas_protobuf.SceneUpdate_pb2 import SceneUpdate
from foxglove_schemas_protobuf.Vector2_pb2 import Vector2
from foxglove_schemas_protobuf.Vector3_pb2 import Vector3
from google.protobuf.message import Message
from google.protobuf.timestamp_pb2 import Timestamp
from mcap.writer import Writer
from mcap_protobuf.schema import register_schema

from tvl_cli import __version__
from tvl_cli.core.contacts import BUMP, EVENTS, NEAR_MISS, TRAPPED
from tvl_cli.core.ring import beam_lines, mm_to_ring
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.runfile import RunTrace

MAP_FRAME, ROBOT_FRAME = "map", "base_link"
MAP, WORLD, TF, POSE, ODOMETRY, SONAR, PERCEIVED, EVENTS_TOPIC = (
    "/map",
    "/world",
    "/tf",
    "/pose",
    "/odometry",
    "/sonar",
    "/perceived",
    "/events",
)
PERCEIVED_SCHEMA = "tvl.PerceivedVelocities"
# Events a person looks into first: contacts and traps.
WARNING_EVENTS = frozenset({BUMP, NEAR_MISS, TRAPPED})
NS_PER_S = 1_000_000_000
# Heights for the 3D view, which draws the plan in the ground plane.
WALL_HEIGHT_M, BODY_HEIGHT_M = 0.5, 0.3
WALL_COLOUR = Color(r=0.2, g=0.2, b=0.2, a=1.0)
BODY_COLOUR = Color(r=0.12, g=0.47, b=0.71, a=0.6)  # the pictures' robot blue
# An echo point: x, y, z as Foxglove places it, then its range, sonar and whether it echoed.
ECHO_POINT = np.dtype(
    [("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("range_m", "<f4"), ("sonar", "u1"), ("echo", "u1")]
)
_FIELD_TYPES = {
    np.dtype("<f4"): PackedElementField.FLOAT32,
    np.dtype("u1"): PackedElementField.UINT8,
}
RING_LOOP_POINTS = 72  # a ring wall drawn as a polygon of 5° sides


@dataclass(frozen=True, slots=True, eq=False)
class Scene:
    """The static world to draw, in metres, in the map frame."""

    segments: tuple[tuple[float, float, float, float], ...]  # walls: x1, y1, x2, y2
    discs: tuple[tuple[float, float, float], ...]  # pillars: x, y, radius
    rings: tuple[tuple[float, float, float], ...]  # ring walls: x, y, radius
    # The world's cells, (rows, columns) int8 top row first: 0 free, 100 occupied, -1 outside.
    occupancy: np.ndarray
    cell_m: float
    origin_m: tuple[float, float]  # the cells' bottom-left corner


@dataclass(frozen=True, slots=True)
class Robot:
    """What the file needs of the robot that ran."""

    radius_m: float
    max_range_m: float
    trajectory_names: tuple[str, ...]


def write_run_mcap(path: Path, trace: RunTrace, scene: Scene, robot: Robot) -> dict[str, int]:
    """Write the run as MCAP, whole or not at all; the messages written on each channel."""
    with atomic_output(path) as temporary, temporary.open("wb") as stream:
        writer = Writer(stream)
        writer.start(profile="", library=f"tvl {__version__}")
        channels = _Channels(writer, robot.trajectory_names)
        channels.write(MAP, 0, _occupancy_grid(scene))
        channels.write(WORLD, 0, _scene_update(scene, robot))
        _write_steps(channels, trace, robot)
        writer.add_metadata(
            "tvl-run",
            {
                "world_name": trace.world_name,
                "world_text": trace.world_text,
                "parameters": json.dumps(trace.parameters, sort_keys=True),
                "metrics": json.dumps(trace.metrics, sort_keys=True),
            },
        )
        writer.finish()
    return channels.counts


class _Channels:
    """Registers each topic's schema and channel on first use, and counts its messages."""

    def __init__(self, writer: Writer, trajectory_names: tuple[str, ...]) -> None:
        self._writer = writer
        self._ids: dict[str, int] = {}
        self.counts: dict[str, int] = {}
        schema = writer.register_schema(
            name=PERCEIVED_SCHEMA,
            encoding="jsonschema",
            data=json.dumps(_perceived_schema(trajectory_names)).encode(),
        )
        self._ids[PERCEIVED] = writer.register_channel(PERCEIVED, "json", schema)
        self.counts[PERCEIVED] = 0

    def write(self, topic: str, time_ns: int, message: Message) -> None:
        if topic not in self._ids:
            schema = register_schema(self._writer, type(message))
            self._ids[topic] = self._writer.register_channel(topic, "protobuf", schema)
            self.counts[topic] = 0
        self._add(topic, time_ns, message.SerializeToString())

    def write_json(self, topic: str, time_ns: int, value: dict[str, Any]) -> None:
        self._add(topic, time_ns, json.dumps(value, allow_nan=False).encode())

    def _add(self, topic: str, time_ns: int, data: bytes) -> None:
        self._writer.add_message(
            self._ids[topic],
            log_time=time_ns,
            data=data,
            publish_time=time_ns,
            sequence=self.counts[topic],
        )
        self.counts[topic] += 1


def _write_steps(channels: _Channels, trace: RunTrace, robot: Robot) -> None:
    arrays = trace.arrays
    period_ns = round(trace.period_s * NS_PER_S)
    ring_m = mm_to_ring(arrays["ring_mm"])  # (N, 16) metres; 0 where the step read none
    _, echoes = beam_lines(ring_m, np.zeros((trace.steps, 3)), robot.radius_m)  # (N, 16, 2)
    events = arrays.get("events", np.zeros(trace.steps, dtype=np.uint8))
    names = robot.trajectory_names
    for step in range(trace.steps):
        # What the step read and chose, at its start: where the last step left the robot.
        read_ns = step * period_ns
        channels.write(SONAR, read_ns, _echo_cloud(read_ns, ring_m[step], echoes[step], robot))
        driven = int(arrays["trajectory"][step])
        channels.write_json(
            PERCEIVED,
            read_ns,
            {
                "timestamp": {"sec": read_ns // NS_PER_S, "nsec": read_ns % NS_PER_S},
                "velocities_mps": {
                    name: None if math.isnan(v) else float(v)
                    for name, v in zip(names, arrays["velocities"][step], strict=True)
                },
                "driven": names[driven] if driven >= 0 else None,
            },
        )
        # Where it ended, and what it began on the way.
        time_ns = (step + 1) * period_ns
        stamp = _stamp(time_ns)
        x, y, theta = arrays["pose"][step]
        channels.write(
            TF,
            time_ns,
            FrameTransform(
                timestamp=stamp,
                parent_frame_id=MAP_FRAME,
                child_frame_id=ROBOT_FRAME,
                translation=Vector3(x=x, y=y, z=0.0),
                rotation=_yaw(theta),
            ),
        )
        for topic, pose in ((POSE, arrays["pose"][step]), (ODOMETRY, arrays["odometry"][step])):
            channels.write(
                topic,
                time_ns,
                PoseInFrame(timestamp=stamp, frame_id=MAP_FRAME, pose=_pose(*pose)),
            )
        for bit, event in enumerate(EVENTS):
            if int(events[step]) & (1 << bit):
                level = Log.WARNING if event in WARNING_EVENTS else Log.INFO
                log = Log(timestamp=stamp, level=level, message=event, name="tvl")
                channels.write(EVENTS_TOPIC, time_ns, log)


def _stamp(time_ns: int) -> Timestamp:
    return Timestamp(seconds=time_ns // NS_PER_S, nanos=time_ns % NS_PER_S)


def _echo_cloud(time_ns: int, ring_m: np.ndarray, echoes: np.ndarray, robot: Robot) -> Message:
    """The ring's 16 echo points in the robot's frame; none if the step read no ring."""
    read = bool(ring_m.any())
    points = np.zeros(len(ring_m) if read else 0, dtype=ECHO_POINT)
    if read:
        points["x"], points["y"] = echoes[:, 0], echoes[:, 1]
        points["range_m"] = ring_m
        points["sonar"] = np.arange(len(ring_m))
        points["echo"] = ring_m < robot.max_range_m
    return PointCloud(
        timestamp=_stamp(time_ns),
        frame_id=ROBOT_FRAME,
        pose=_pose(0.0, 0.0, 0.0),
        point_stride=ECHO_POINT.itemsize,
        fields=[
            PackedElementField(name=name, offset=offset, type=_FIELD_TYPES[dtype])
            for name, (dtype, offset, *_) in (ECHO_POINT.fields or {}).items()
        ],
        data=points.tobytes(),
    )


def _occupancy_grid(scene: Scene) -> Grid:
    """The world's cells as Foxglove's grid: rows from the bottom (y up), one int8 a cell."""
    columns = scene.occupancy.shape[1]
    x0, y0 = scene.origin_m
    return Grid(
        timestamp=Timestamp(),
        frame_id=MAP_FRAME,
        pose=_pose(x0, y0, 0.0),
        column_count=columns,
        cell_size=Vector2(x=scene.cell_m, y=scene.cell_m),
        row_stride=columns,
        cell_stride=1,
        fields=[PackedElementField(name="occupancy", offset=0, type=PackedElementField.INT8)],
        data=np.ascontiguousarray(scene.occupancy[::-1], dtype=np.int8).tobytes(),
    )


def _scene_update(scene: Scene, robot: Robot) -> SceneUpdate:
    """The world's walls, rings and discs, drawn once and kept; and the robot's body."""
    walls = LinePrimitive(
        type=LinePrimitive.LINE_LIST,
        pose=_pose(0.0, 0.0, 0.0),
        thickness=0.02,
        points=[
            Point3(x=x, y=y, z=0.0)
            for x1, y1, x2, y2 in scene.segments
            for x, y in ((x1, y1), (x2, y2))
        ],
        color=WALL_COLOUR,
    )
    angles = np.linspace(0.0, 2.0 * math.pi, RING_LOOP_POINTS, endpoint=False)
    rings = [
        LinePrimitive(
            type=LinePrimitive.LINE_LOOP,
            pose=_pose(x, y, 0.0),
            thickness=0.02,
            points=[Point3(x=r * math.cos(a), y=r * math.sin(a), z=0.0) for a in angles],
            color=WALL_COLOUR,
        )
        for x, y, r in scene.rings
    ]
    discs = [_cylinder(x, y, r, WALL_HEIGHT_M, WALL_COLOUR) for x, y, r in scene.discs]
    world = SceneEntity(
        timestamp=Timestamp(),
        frame_id=MAP_FRAME,
        id="world",
        lines=[walls, *rings],
        cylinders=discs,
    )
    body = SceneEntity(
        timestamp=Timestamp(),
        frame_id=ROBOT_FRAME,
        id="robot",
        frame_locked=True,  # moves with the robot's frame
        cylinders=[_cylinder(0.0, 0.0, robot.radius_m, BODY_HEIGHT_M, BODY_COLOUR)],
    )
    return SceneUpdate(entities=[world, body])


def _cylinder(
    x: float, y: float, radius_m: float, height_m: float, colour: Color
) -> CylinderPrimitive:
    return CylinderPrimitive(
        pose=Pose(position=Vector3(x=x, y=y, z=height_m / 2.0), orientation=_yaw(0.0)),
        size=Vector3(x=2.0 * radius_m, y=2.0 * radius_m, z=height_m),
        bottom_scale=1.0,
        top_scale=1.0,
        color=colour,
    )


def _pose(x: float, y: float, theta: float) -> Pose:
    return Pose(position=Vector3(x=x, y=y, z=0.0), orientation=_yaw(theta))


def _yaw(theta: float) -> Quaternion:
    """A turn of theta radians about +z."""
    return Quaternion(x=0.0, y=0.0, z=math.sin(theta / 2.0), w=math.cos(theta / 2.0))


def _perceived_schema(trajectory_names: tuple[str, ...]) -> dict[str, Any]:
    """The JSON Schema of a /perceived message."""
    speed = {"type": ["number", "null"], "description": "perceived velocity, m/s"}
    return {
        "title": PERCEIVED_SCHEMA,
        "description": "The velocities a TVL robot perceived for its trajectories at one step",
        "type": "object",
        "properties": {
            "timestamp": {
                "type": "object",
                "properties": {"sec": {"type": "integer"}, "nsec": {"type": "integer"}},
            },
            "velocities_mps": {
                "type": "object",
                "properties": {name: speed for name in trajectory_names},
            },
            "driven": {
                "type": ["string", "null"],
                "description": "the trajectory driven; null spinning, reversing or trapped",
            },
        },
    }
