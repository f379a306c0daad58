"""The robot as a Gymnasium environment, `tvl/SonarRing-v0`, with TVL and Q-learning agents.

The robot, its sonar ring and the worlds make the environment, with the paper's TVL policy
and the Q-learning baseline as agents over it (`tvl[gym]`).

Gymnasium 1.x loads no plugins by entry point, so importing this package registers the
environment: `gymnasium.make("tvl_cli.gym:tvl/SonarRing-v0")` imports it on the way, and
`gymnasium.make_vec` makes its vector environment, many robots in one world a step. Nothing
else in tvl imports this package, so tvl works without Gymnasium installed.
"""

import gymnasium

from tvl_cli.core.competence import COMPETENCE_RUN_MINUTES
from tvl_cli.gym.env import ACTION_NAMES, ROBOT, TASKS, SonarRingEnv, resolve_world
from tvl_cli.gym.policies import QTableAgent, TvlGymPolicy
from tvl_cli.gym.vector import SonarRingVectorEnv

ENV_ID = "tvl/SonarRing-v0"
# An episode lasts at most a competence run (5 simulated minutes), unless a bump ends it.
MAX_EPISODE_STEPS = round(COMPETENCE_RUN_MINUTES * 60.0 / ROBOT.control_period_s)

gymnasium.register(
    id=ENV_ID,
    entry_point="tvl_cli.gym.env:SonarRingEnv",
    vector_entry_point="tvl_cli.gym.vector:SonarRingVectorEnv",
    max_episode_steps=MAX_EPISODE_STEPS,
)

__all__ = [
    "ACTION_NAMES",
    "ENV_ID",
    "MAX_EPISODE_STEPS",
    "TASKS",
    "QTableAgent",
    "SonarRingEnv",
    "SonarRingVectorEnv",
    "TvlGymPolicy",
    "actions",
    "env",
    "policies",
    "resolve_world",
    "scoring",
    "task",
    "vector",
]
