"""Control steps in the lab: a full sonar-ring scan plus one physics step, and the ring alone.

    python benchmarks/sim_speed.py [--steps N] [--repeats R] [--json]

The robot wanders the lab (an arc while the way ahead is clear, a spin otherwise), so the
timing includes contacts and every kind of obstacle. Each figure is the median CPU time of
R timed runs, beside the same work done in the same run by the baselines: the ring cast by
its plain numpy reference (core/kernels/ring_reference.py), and by pymunk's own
segment_query_first, one call a ray.
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pymunk
from timing import cpu_seconds, figure_line

from tvl_cli.core.drive_command import Command
from tvl_cli.core.kernels.ring_reference import ring_ranges_reference
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap, load_world

LAB = Path(__file__).resolve().parent.parent / "worlds" / "lab.txt"
WARM_UP_STEPS = 200
TARGET_STEP_US = 30.0


def wander(sim: Simulator, steps: int) -> None:
    """`steps` control steps of sense, decide, act."""
    ahead = sim.robot.trajectories[sim.robot.trajectory_index("T1L")]
    forward, turn = Command.follow(ahead, 0.4), Command.spin(1.0)
    for _ in range(steps):
        readings = sim.read_sonar()
        sim.step(forward if readings[0] > 0.6 else turn)


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
    figures = {
        "step_us": 1e6 * step_s,
        "step_with_numpy_ring_us": 1e6 * reference_step_s,
        "ring_us": 1e6 * ring_s,
        "numpy_ring_us": 1e6 * reference_ring_s,
        "pymunk_ring_us": 1e6 * pymunk_s,
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


if __name__ == "__main__":
    main()
