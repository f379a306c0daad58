"""Train an agent on tvl/SonarRing-v0 through Gymnasium's standard loop, then judge it.

The agent is the Q-learning baseline's learner (tvl_cli.baselines.qtable.QTable): action
values over the 720 rules of the paper's single FAM, one rule (the strongest) a sonar ring,
and the seven trajectory actions. Any agent that takes a Box observation and a Discrete (or,
with `action_type="continuous"`, a Box) action plugs into the same loop; with PyTorch and
stable-baselines3 installed, `stable_baselines3.PPO("MlpPolicy", env).learn(5000)` is one.

From the repository's top folder:

    python docs/examples/gym_q_learning.py [--steps 5000] [--seed 1] [--world circle]
"""

from __future__ import annotations

import argparse

import gymnasium
import numpy as np
from gymnasium.wrappers import RecordEpisodeStatistics

from tvl_cli.baselines.qlearning import QLearning, empty_table
from tvl_cli.baselines.qtable import QTable
from tvl_cli.core.competence import COMPETENCE_RUN_MINUTES, is_competent
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.gym import ENV_ID, resolve_world  # importing tvl_cli.gym registers the env
from tvl_cli.gym.env import ROBOT


def train(env: gymnasium.Env, table: QTable, steps: int, seed: int) -> list[float]:
    """Epsilon-greedy Q-learning for `steps` environment steps; each episode's return.

    A bump ends an episode, and the next goes on from where it happened, backed off along
    the path (`reset(options={"continue": True})`), as the robot learns in the paper: started
    afresh each time, it would learn little but the first metres from the start.
    """
    explore = np.random.default_rng(seed)
    returns = []
    obs, _ = env.reset(seed=seed)
    state = table.state(obs)
    for _ in range(steps):
        action = table.act(state, explore)
        obs, reward, terminated, truncated, info = env.step(action)
        after = table.state(obs)
        # A bump ends the episode: nothing is bootstrapped after it. A time limit does not.
        table.learn(state, action, float(reward), None if terminated else after)
        if terminated or truncated:
            returns.append(float(info["episode"]["r"]))
            obs, _ = env.reset(options={"continue": terminated})
            after = table.state(obs)
        state = after
    return returns


def judge(world: str, table: QTable, seed: int) -> RunMetrics:
    """The baseline's own judge: a greedy five-minute run of the table from the world's
    start, through the drive loop `tvl run` uses (a bump does not end it)."""
    learner = QLearning(resolve_world(world), ROBOT, seed)
    learner.q[:] = table.q
    return learner.evaluate(COMPETENCE_RUN_MINUTES, seed)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=5000, help="training steps (0.1 s each)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--world", default="circle", help="a bundled world or a map's path")
    args = parser.parse_args()

    # The paper's method observes the live ring, as the baseline's judge reads it (ours would
    # observe its echo memory's virtual ring).
    env = gymnasium.make(ENV_ID, world=args.world, task="avoid", method="paper")
    env = RecordEpisodeStatistics(env)
    # Actions 0-6, T3L .. T3R at their top speed: the spins and the stop are left unused.
    table = empty_table(ROBOT)
    for label, steps in (("untrained", 0), ("trained", args.steps)):
        returns = train(env, table, steps, args.seed)
        run = judge(args.world, table, args.seed)
        print(
            f"{label}: {steps} steps, {len(returns)} episodes; greedy for "
            f"{COMPETENCE_RUN_MINUTES:g} minutes: {run.contacts_per_min:.1f} contacts a minute, "
            f"{run.mean_speed_mps:.2f} m/s, {'competent' if is_competent(run) else 'not competent'}"
        )


if __name__ == "__main__":
    main()
