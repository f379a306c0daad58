"""Control steps in the lab: a full sonar-ring scan plus one physics step, the ring alone,
and the echo memory's work a step.

    python benchmarks/sim_speed.py [--steps N] [--repeats R] [--json]

The robot wanders the lab (an arc while the way ahead is clear, a spin otherwise), so the
timing includes contacts and every kind of obstacle. Each figure is the median CPU time of
R timed runs, beside the same work done in the same run by the baselines: the ring cast by
its plain numpy reference (tests/kernel_references/ring_reference.py), and by pymunk's own
segment_query_first, one call a ray; the echo memory's cast by its numpy reference
(tests/kernel_references/memory_reference.py). The echo memory (the default) is fed the wander's
readings step by step, already full when timed: a step is remembering the reading and
casting the virtual ring. Its figure is the median of REPEATS_OF_MEMORY runs whatever R:
each is a whole wander's worth of steps, the numpy cast's a fifth of one.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pymunk
from timing import cpu_seconds, figure_line

from tvl_cli.agent.perception import EchoMemory
from tvl_cli.agent.policy import Pose
from tvl_cli.core.drive_command import Command
from tvl_cli.core.memory import DEFAULT_MEMORY
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap, load_world

# The numpy references the kernels' tests hold them to.
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from kernel_references.memory_reference import remembered_ranges_reference
from kernel_references.ring_reference import ring_ranges_reference

LAB = Path(__file__).resolve().parent.parent / "worlds" / "lab.txt"
WARM_UP_STEPS = 200
REPEATS_OF_MEMORY = 3
TARGET_STEP_US = 30.0


Reading = tuple[Pose, np.ndarray]  # where the robot read a ring (16,) metres


def wander(sim: Simulator, steps: int, readings: list[Reading] | None = None) -> None:
    """`steps` control steps of sense, decide, act, each pose and ring kept in `readings`."""
    ahead = sim.robot.trajectories[sim.robot.trajectory_index("T1L")]
    forward, turn = Command.follow(ahead, 0.4), Command.spin(1.0)
    for _ in range(steps):
        ring = sim.read_sonar()
        if readings is not None:
            readings.append((sim.pose, ring))
        sim.step(forward if ring[0] > 0.6 else turn)


def echo_memory_steps(robot: RobotConfig, readings: list[Reading], reference: bool) -> float:
    """Median CPU seconds a step of the default echo memory fed `readings` in turn: full of
    them before it is timed, cast by the kernel or by its numpy reference."""
    memory = EchoMemory(DEFAULT_MEMORY, robot)
    if reference:
        memory._cast = remembered_ranges_reference
    step = 0

    def feed(count: int) -> None:
        nonlocal step
        for _ in range(count):
            pose, ring = readings[step % len(readings)]
            memory.sense(step, pose, ring)
            step += 1

    feed(memory.window_steps)
    count = len(readings) // 5 if reference else len(readings)  # the numpy cast is slow
    return cpu_seconds(lambda: feed(count), REPEATS_OF_MEMORY) / count


def pymunk_ring(world: WorldMap, sim: Simulator) -> Callable[[], None]:
    """One ring scan cast ray by ray with pymunk's segment_query_first, nearest hits alone."""
    space = pymunk.Space()
    space.add(*[pymunk.Segment(space.static_body, s[:2], s[2:], 0.0) for s in world.segments])
    space.add(*[pymunk.Circle(space.static_body, r, (x, y)) for x, y, r in world.discs])
    origins, directions = sim.sonar.rays(sim.pose)
    starts = [tuple(o) for o in origins]
    ends = [
        tuple(o + sim.robot.sonar.max_range_m * d) for o, d in zip(origins, directions, strict=True)
    ]
    everything = pymunk.ShapeFilter()

    def scan() -> None:
        nearest = np.full(len(starts), np.inf)  # (16 * rays,) fraction of the maximum range
        for i, (start, end) in enumerate(zip(starts, ends, strict=True)):
            info = space.segment_query_first(start, end, 0.0, everything)
            if info is not None:
                nearest[i] = info.alpha
        nearest.reshape(sim.robot.sonar.count, -1).min(axis=1)

    return scan


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=5000, help="control steps a timed run")
    parser.add_argument("--repeats", type=int, default=5, help="timed runs; the median counts")
    parser.add_argument("--json", action="store_true", help="print only the figures, as JSON")
    args = parser.parse_args()

    world = load_world(LAB)
    robot = RobotConfig()
    compiled = Simulator(world, robot, np.random.default_rng(0))
    reference = Simulator(world, robot, np.random.default_rng(0))
    reference.sonar._ring_ranges = ring_ranges_reference  # the same ring, cast by numpy
    for sim in (compiled, reference):
        wander(sim, WARM_UP_STEPS)
    steps = args.steps
    step_s = cpu_seconds(lambda: wander(compiled, steps), args.repeats) / steps
    # The numpy ring is slow: a fifth of the steps time it as well.
    reference_step_s = cpu_seconds(lambda: wander(reference, steps // 5), args.repeats)
    reference_step_s /= steps // 5
    scans = max(steps // 5, 100)

    def ring_scans(sim: Simulator) -> Callable[[], None]:
        def scan() -> None:
            for _ in range(scans):
                sim.read_sonar()

        return scan

    ring_s = cpu_seconds(ring_scans(compiled), args.repeats) / scans
    reference_ring_s = cpu_seconds(ring_scans(reference), args.repeats) / scans
    pymunk_scan = pymunk_ring(world, compiled)
    pymunk_s = cpu_seconds(lambda: [pymunk_scan() for _ in range(scans)], args.repeats) / scans
    readings: list[Reading] = []
    wander(compiled, steps, readings)
    memory_s = echo_memory_steps(robot, readings, reference=False)
    reference_memory_s = echo_memory_steps(robot, readings, reference=True)
    figures = {
        "step_us": 1e6 * step_s,
        "step_with_numpy_ring_us": 1e6 * reference_step_s,
        "ring_us": 1e6 * ring_s,
        "numpy_ring_us": 1e6 * reference_ring_s,
        "pymunk_ring_us": 1e6 * pymunk_s,
        "echo_memory_us": 1e6 * memory_s,
        "numpy_echo_memory_us": 1e6 * reference_memory_s,
        "realtime_factor": robot.control_period_s / step_s,
    }
    if args.json:
        print(json.dumps({k: round(v, 2) for k, v in figures.items()}))
        return
    f = figures
    print(f"{world.name}: {len(world.segments)} wall segments, {len(world.discs)} discs; "
          f"median CPU time of {args.repeats} runs")  # fmt: skip
    print(
        figure_line(
            f"control step (16 x {robot.sonar.rays_per_beam}-ray scan + physics)",
            f"{f['step_us']:.1f} µs",
            f"<= {TARGET_STEP_US:g} µs",
            f["step_us"] <= TARGET_STEP_US,
            f"{f['step_with_numpy_ring_us'] / f['step_us']:.1f}x as fast as with the numpy "
            f"ring ({f['step_with_numpy_ring_us']:.1f} µs); {f['realtime_factor']:,.0f}x real time",
        )
    )
    print(
        figure_line(
            "ring scan",
            f"{f['ring_us']:.1f} µs",
            None,
            None,
            f"{f['numpy_ring_us'] / f['ring_us']:.1f}x as fast as numpy ({f['numpy_ring_us']:.1f}"
            f" µs), {f['pymunk_ring_us'] / f['ring_us']:.1f}x pymunk's ray queries "
            f"({f['pymunk_ring_us']:.1f} µs)",
        )
    )
    print(
        figure_line(
            f"echo memory ({DEFAULT_MEMORY.window_s:g} s of {DEFAULT_MEMORY.kind}): "
            "remember + cast",
            f"{f['echo_memory_us']:.1f} µs",
            None,
            None,
            f"{f['numpy_echo_memory_us'] / f['echo_memory_us']:.1f}x as fast as with the numpy "
            f"cast ({f['numpy_echo_memory_us']:.1f} µs)",
        )
    )


if __name__ == "__main__":
    main()
