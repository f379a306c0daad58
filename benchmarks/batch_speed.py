"""Many robots a step in the lab: CPU time per robot-step (ring + physics) of a RobotBatch of
N robots, against N separate Simulators doing the same work in the same run.

    python benchmarks/batch_speed.py [--robot-steps K] [--repeats R] [--json]

Each robot wanders as in sim_speed.py (an arc while the way ahead is clear, a spin
otherwise) from its own free pose in the lab, drawn from a fixed seed; the separate
Simulators start from the same poses with the same generators, so both do the same steps.
Each repeat times the batch and then the Simulators for K robot-steps each; the figures are
the medians, and the ratio the median of the repeats' paired ratios. At N = 64 the batch's
ring is also timed alone: the rest of a robot-step is the physics, the odometry and the
choice of command.

Last, whole behaviour runs: RUNS `avoid` runs of the lab (seeds 1..RUNS, a single FAM
trained from logs/lab-s1.h5, our method), driven together in one batch
(agent.drive_tvl.behave_together) against the same runs driven alone, one after another:
what the batch saves once each robot's perception, choice and reflexes are counted too. The
figures are medians of min(R, 3) pairs (a pair takes seconds), taken in turn, together first
and alone first, after an untimed short run has loaded the kernels.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from collections.abc import Callable

import numpy as np
from sim_speed import LAB, wander
from timing import figure_line

from tvl_cli.agent.drive_tvl import BehaviourRun, behave, behave_together
from tvl_cli.commands.train import train_from_logs
from tvl_cli.core.drive_command import Command
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.batch import RobotBatch
from tvl_cli.sim.geometry import clearances_m
from tvl_cli.sim.motion import Pose
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap, load_world

SIZES = (1, 8, 64)
EXAMPLE_LOG = LAB.parent.parent / "logs" / "lab-s1.h5"
RUNS = 8
RUN_MINUTES = 3.0
TARGET_SIZE = 64
TARGET_ROBOT_STEP_US = 10.0
WARM_UP_STEPS = 100
# A start pose leaves this much room around the body.
START_CLEARANCE_M = 0.1


def free_poses(world: WorldMap, robot: RobotConfig, count: int, seed: int) -> list[Pose]:
    """`count` poses whose bodies touch nothing, uniform over the world's free space."""
    geometry = RobotBatch(world, robot, [np.random.default_rng(0)]).geometry
    rng = np.random.default_rng(seed)
    poses: list[Pose] = []
    while len(poses) < count:
        x, y = rng.uniform(0.0, world.width_m), rng.uniform(0.0, world.height_m)
        if clearances_m(geometry, np.array([[x, y]]), robot.radius_m)[0] > START_CLEARANCE_M:
            poses.append((x, y, rng.uniform(-np.pi, np.pi)))
    return poses


def wander_batch(batch: RobotBatch, steps: int) -> None:
    """`steps` control steps of every robot, deciding as sim_speed.wander does."""
    ahead = batch.robot.trajectories[batch.robot.trajectory_index("T1L")]
    forward, turn = Command.follow(ahead, 0.4), Command.spin(1.0)
    for _ in range(steps):
        readings = batch.read_sonar()
        batch.step([forward if front > 0.6 else turn for front in readings[:, 0].tolist()])


def cpu_s(run: Callable[[], object]) -> float:
    started = time.process_time()
    run()
    return time.process_time() - started


def measure(world: WorldMap, robot: RobotConfig, size: int, args: argparse.Namespace) -> dict:
    """µs per robot-step of a batch of `size` and of `size` Simulators, paired."""
    poses = free_poses(world, robot, size, seed=size)
    batch = RobotBatch(world, robot, [np.random.default_rng(i) for i in range(size)])
    sims = [Simulator(world, robot, np.random.default_rng(i)) for i in range(size)]
    for i, (sim, pose) in enumerate(zip(sims, poses, strict=True)):
        batch.place(i, *pose)
        sim.place(*pose)
    wander_batch(batch, WARM_UP_STEPS)
    for sim in sims:
        wander(sim, WARM_UP_STEPS)
    steps = max(args.robot_steps // size, 1)
    robot_steps = steps * size
    together, apart = [], []
    for _ in range(args.repeats):
        together.append(cpu_s(lambda: wander_batch(batch, steps)) / robot_steps)
        apart.append(cpu_s(lambda: [wander(sim, steps) for sim in sims]) / robot_steps)
    figures = {
        "batch_us": 1e6 * statistics.median(together),
        "simulators_us": 1e6 * statistics.median(apart),
        "speedup": statistics.median(a / t for t, a in zip(together, apart, strict=True)),
    }
    if size == TARGET_SIZE:
        ring = [cpu_s(lambda: [batch.read_sonar() for _ in range(steps)]) for _ in together]
        figures["ring_us"] = 1e6 * statistics.median(ring) / robot_steps
    return figures


def runs_together(world: WorldMap, robot: RobotConfig, fam: Fam, repeats: int) -> dict:
    """CPU seconds of RUNS behaviour runs driven together and alone, paired (in turn, each
    first in every other pair), and the median of the pairs' ratios."""
    runs = [BehaviourRun(fam, "avoid", seed, None) for seed in range(1, RUNS + 1)]

    def together() -> None:
        behave_together(world, robot, runs, minutes=RUN_MINUTES, method=DEFAULT)

    def alone() -> None:
        for run in runs:
            behave(world, robot, fam, "avoid", minutes=RUN_MINUTES, seed=run.seed, method=DEFAULT)

    behave(world, robot, fam, "avoid", minutes=0.1, seed=1, method=DEFAULT)  # loads kernels
    pairs = []
    for repeat in range(repeats):
        if repeat % 2:
            alone_s = cpu_s(alone)
            pairs.append((cpu_s(together), alone_s))
        else:
            pairs.append((cpu_s(together), cpu_s(alone)))
    return {
        "together_s": statistics.median(t for t, _ in pairs),
        "alone_s": statistics.median(a for _, a in pairs),
        "speedup": statistics.median(a / t for t, a in pairs),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--robot-steps", type=int, default=12800, help="robot-steps a timed run (all robots)"
    )
    parser.add_argument("--repeats", type=int, default=5, help="timed runs; the median counts")
    parser.add_argument("--json", action="store_true", help="print only the figures, as JSON")
    args = parser.parse_args()

    world = load_world(LAB)
    robot = RobotConfig()
    results = {f"n{size}": measure(world, robot, size, args) for size in SIZES}
    fam = train_from_logs([EXAMPLE_LOG], SINGLE).fam
    results["runs"] = runs_together(world, robot, fam, min(args.repeats, 3))
    if args.json:
        print(json.dumps({n: {k: round(v, 2) for k, v in f.items()} for n, f in results.items()}))
        return
    print(f"{world.name}: CPU µs per robot-step (16 x {robot.sonar.rays_per_beam}-ray scan + "
          f"physics), median of {args.repeats} runs of {args.robot_steps} robot-steps")  # fmt: skip
    for size in SIZES:
        f = results[f"n{size}"]
        target = size == TARGET_SIZE
        print(
            figure_line(
                f"batch of {size}",
                f"{f['batch_us']:.1f} µs",
                f"<= {TARGET_ROBOT_STEP_US:g} µs" if target else None,
                f["batch_us"] <= TARGET_ROBOT_STEP_US if target else None,
                f"{f['speedup']:.2f}x as fast as {size} Simulators ({f['simulators_us']:.1f} µs)"
                ", paired",
            )
        )
    f = results[f"n{TARGET_SIZE}"]
    print(
        figure_line(
            f"  of which ring, batch of {TARGET_SIZE}",
            f"{f['ring_us']:.1f} µs",
            None,
            None,
            f"the rest (physics, odometry, choice): {f['batch_us'] - f['ring_us']:.1f} µs",
        )
    )
    f = results["runs"]
    print(
        figure_line(
            f"{RUNS} avoid runs of {RUN_MINUTES:g} min, together",
            f"{f['together_s']:.2f} s",
            None,
            None,
            f"{f['speedup']:.2f}x as fast as alone ({f['alone_s']:.2f} s), paired",
        )
    )


if __name__ == "__main__":
    main()
