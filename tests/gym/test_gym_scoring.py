"""Which runs a controller is scored on: a saved model only on the task whose observation it
learnt on (an avoider's 16 ranges cannot take a goal's bearing and distance too), a Python
policy on every task."""

from __future__ import annotations

from pathlib import Path

import pytest

from tvl_cli.core.method import DEFAULT
from tvl_cli.gym.scoring import LoadedController, load_controller
from tvl_cli.sim.worldmap import WorldMap, load_world

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def world() -> WorldMap:
    return load_world(ROOT / "worlds" / "obstacles.txt")


def never_called(observation: object) -> int:
    raise AssertionError("a controller is not run to tell what it observes")


@pytest.mark.parametrize(
    ("shape", "avoids", "seeks_goals"), [((16,), True, False), ((18,), False, True)]
)
def test_a_model_is_scored_only_on_the_task_it_observes(
    world: WorldMap, shape: tuple[int, ...], avoids: bool, seeks_goals: bool
) -> None:
    model = LoadedController(lambda: never_called, shape)
    assert model.observes(world, None, DEFAULT) is avoids
    assert model.observes(world, world.goals[0], DEFAULT) is seeks_goals


def test_a_python_policy_is_scored_on_every_task(world: WorldMap, tmp_path: Path) -> None:
    policy = tmp_path / "ahead.py"
    policy.write_text("def act(observation):\n    return 3\n")
    loaded = load_controller(f"{policy}:act")
    assert loaded.observation_shape is None
    assert loaded.observes(world, None, DEFAULT) and loaded.observes(world, world.goals[0], DEFAULT)
    assert loaded.make()([0.0] * 16) == 3
