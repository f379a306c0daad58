"""Control steps per second in the lab: a full sonar-ring scan plus one physics step.

    python benchmarks/sim_speed.py [--steps N] [--repeats R] [--json]

The robot wanders the lab (an arc while the way ahead is clear, a spin otherwise), so the
timing includes contacts and every kind of obstacle. The best of R timed runs is reported,
as timing noise on a shared machine only ever adds time. Without --json it also times the
same ring cast with pymunk's own segment_query_first, one call a ray, for comparison.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
import pymunk

from tvl_cli.core.command import Command
from tvl_cli.core.config import RobotConfig
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap, load_world

LAB = Path(__file__).resolve().parent.parent / "worlds" / "lab.txt"
WARM_UP_STEPS = 200


def time_control_steps(sim: Simulator, steps: int) -> float:
    """Seconds for `steps` control steps of sense, decide, act."""
    ahead = sim.robot.trajectories[sim.robot.trajectory_index("T1L")]
    wander, turn = Command.follow(ahead, 0.4), Command.spin(1.0)
    started = time.perf_counter()
    for _ in range(steps):
        readings = sim.read_sonar()
        sim.step(wander if readings[0] > 0.6 else turn)
    return time.perf_counter() - started


def time_pymunk_ring(world: WorldMap, sim: Simulator, scans: int) -> float:
    """Seconds for `scans` ring scans cast ray by ray with pymunk's segment_query_first."""
    space = pymunk.Space()
    space.add(*[pymunk.Segment(space.static_body, s[:2], s[2:], 0.0) for s in world.segments])
    space.add(*[pymunk.Circle(space.static_body, r, (x, y)) for x, y, r in world.discs])
    origins, directions = sim.sonar.rays(sim.pose)
    starts = [tuple(o) for o in origins]
    ends = [
        tuple(o + sim.robot.sonar.max_range_m * d) for o, d in zip(origins, directions, strict=True)
    ]
    everything = pymunk.ShapeFilter()
    started = time.perf_counter()
    for _ in range(scans):
        nearest = np.full(len(starts), np.inf)  # (16 * rays,) fraction of the maximum range
        for i, (start, end) in enumerate(zip(starts, ends, strict=True)):
            info = space.segment_query_first(start, end, 0.0, everything)
            if info is not None:
                nearest[i] = info.alpha
        nearest.reshape(sim.robot.sonar.count, -1).min(axis=1)
    return time.perf_counter() - started


def time_numpy_ring(sim: Simulator, scans: int) -> float:
    """Seconds for `scans` ring scans by the simulator's own vectorised caster."""
    started = time.perf_counter()
    for _ in range(scans):
        sim.read_sonar()
    return time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=5000, help="control steps a timed run")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs; the best counts")
    parser.add_argument("--json", action="store_true", help="print only the figures, as JSON")
    args = parser.parse_args()

    world = load_world(LAB)
    robot = RobotConfig()
    sim = Simulator(world, robot, np.random.default_rng(0))
    time_control_steps(sim, WARM_UP_STEPS)
    best_s = min(time_control_steps(sim, args.steps) for _ in range(args.repeats))
    steps_per_s = args.steps / best_s
    realtime_factor = steps_per_s * robot.control_period_s
    if args.json:
        print(
            json.dumps(
                {"steps_per_s": round(steps_per_s, 1), "realtime_factor": round(realtime_factor, 1)}
            )
        )
        return
    print(f"world {LAB.name}: {len(world.segments)} wall segments, {len(world.discs)} discs")
    print(
        f"control step (16 x {robot.sonar.rays_per_beam} ray scan + physics): "
        f"{1e6 * best_s / args.steps:.1f} us"
    )
    print(f"control steps per second: {steps_per_s:,.0f}")
    print(f"real-time factor at {1 / robot.control_period_s:g} Hz: {realtime_factor:,.0f}x")
    scans = max(args.steps // 5, 100)
    numpy_s = min(time_numpy_ring(sim, scans) for _ in range(args.repeats)) / scans
    pymunk_s = min(time_pymunk_ring(world, sim, scans) for _ in range(args.repeats)) / scans
    print(
        f"ring scan: numpy {1e6 * numpy_s:.1f} us; pymunk segment_query_first, nearest hits "
        f"alone, {1e6 * pymunk_s:.1f} us ({pymunk_s / numpy_s:.1f}x the numpy cost)"
    )


if __name__ == "__main__":
    main()
