"""Train PPO (Stable-Baselines3) on tvl/SonarRing-v0, then score it with `tvl bench`.

The agent learns the avoid task in tuning worlds (`tvl world new rooms --seed N`, N from 1:
never the test worlds), observing what the environment observes by default (our echo
memory's virtual ring, the ring a FAM of ours reads), and is saved as a model file. `tvl
bench generalization --controller ppo=PPO:FILE.zip` then drives it in the test worlds with
the same robot, sonar, seeds and metrics as ours, its rows beside ours.

It needs the RL extra, kept out of the CI install for its size (PyTorch):

    pip install torch==2.13.0 && pip install -e ".[gym,rl]"
    python docs/examples/ppo_bench.py [--steps 50000] [--size quick] [--out results/ppo]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

import gymnasium
from stable_baselines3 import PPO

import tvl_cli.gym  # noqa: F401  (registers tvl/SonarRing-v0)
from tvl_cli.sim.worldgen import generate_world
from tvl_cli.sim.worldmap import parse_world

TUNING_WORLDS = (1, 2, 3, 4)


def train(steps: int, seed: int, model_path: Path) -> None:
    """PPO on the avoid task, its steps shared among the tuning worlds in turn."""
    model = None
    for number, world_seed in enumerate(TUNING_WORLDS):
        world = parse_world(generate_world("rooms", None, None, world_seed), f"rooms-s{world_seed}")
        env = gymnasium.make("tvl/SonarRing-v0", world=world, task="avoid")
        if model is None:
            model = PPO("MlpPolicy", env, seed=seed, verbose=0, device="cpu")
        else:
            model.set_env(env)
        model.learn(steps // len(TUNING_WORLDS), reset_num_timesteps=number == 0)
    assert model is not None
    model.save(model_path)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=50_000, help="training steps (0.1 s each)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--size", choices=("tiny", "quick", "full"), default="quick")
    parser.add_argument("--out", type=Path, default=Path("results") / "ppo")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    model_path = args.out / "ppo-avoid.zip"
    if not model_path.exists():
        train(args.steps, args.seed, model_path)
    tvl = Path(sys.executable).with_name("tvl")
    bench = ["bench", "generalization", "--size", args.size, "--out", str(args.out / "bench")]
    command = [str(tvl), *bench, "--controller", f"ppo=PPO:{model_path}"]
    print(" ".join(command[1:]), flush=True)
    subprocess.run(command, check=True)


if __name__ == "__main__":
    main()
