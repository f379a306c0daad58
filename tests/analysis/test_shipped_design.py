"""The shipped `designed` configuration is what `tvl design` chooses from its tuning logs."""

from __future__ import annotations

from dataclasses import replace

import pytest

from tvl_cli.agent.explore import Learner
from tvl_cli.analysis.input_selection import design_inputs
from tvl_cli.core.episode import Episode
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import DESIGNED, SINGLE
from tvl_cli.core.labels import BUMP_LABELS
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.training import TrainParams, driven_labels
from tvl_cli.sim.worldgen import generate_world
from tvl_cli.sim.worldmap import parse_world

# As the shipped design was made: 15 simulated minutes in each of rooms seeds 1 to
# 10, learning seed 1, every default; the design with seed 1 and the default budget.
TUNING_WORLD_SEEDS = range(1, 11)
TUNING_MINUTES = 15.0
LABELS_THEN = {"labels": BUMP_LABELS, "decel_mps2": 0.1, "label_ceiling": 1.0}


def tuning_episodes() -> list[Episode]:
    # Our method on the live ring, labelling the driven trajectories alone: as the design was
    # made, before there was an echo memory or heard labels, and while ours braked at 0.1 m/s²
    # with labels capped at the top speed.
    robot, method = RobotConfig(), replace(DEFAULT, memory=NO_MEMORY, **LABELS_THEN)
    names = [t.name for t in robot.trajectories]
    episodes: list[Episode] = []
    for world_seed in TUNING_WORLD_SEEDS:
        world = parse_world(generate_world("rooms", None, None, world_seed), "rooms")
        fam = Fam(SINGLE, names)
        learner = Learner(world, robot, fam, LearnParams(minutes=TUNING_MINUTES), method, 1)
        learner.run(episodes.append, lambda _minute: None)
    return episodes


@pytest.mark.slow  # over a second
def test_the_shipped_designed_configuration_is_designed_again_from_the_tuning_logs() -> None:
    driven = TrainParams(**LABELS_THEN)
    labelled = [driven_labels(e, len(RobotConfig().trajectories)) for e in tuning_episodes()]
    design = design_inputs(labelled, RobotConfig(), driven, seed=1)
    assert design.config.tables == DESIGNED.tables
