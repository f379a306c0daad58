"""A controller of `tvl/SonarRing-v0`, scored as `tvl run` scores a FAM: driven by the same
loop (agent.drive) from the world's start, with the same robot, sonar, seed and metrics.

A controller maps what the environment observes to one of its actions. It is either
- a Gymnasium policy, `MODULE:CALLABLE` (a module on the path, or `FILE.py:CALLABLE`): a
  callable taking an observation; a class is made anew (with no arguments) for each run, and
  a callable with a `reset()` is reset before each run;
- a saved Stable-Baselines3 model, `ALGORITHM:FILE.zip` (e.g. `PPO:ppo-avoid.zip`), which acts
  deterministically.

The run ends when its time is up or its goal is reached, never at a bump: a bump ends the
environment's episode, but a run is judged on every contact, as TVL's runs are.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.agent.drive import drive_engine
from tvl_cli.agent.engine import StepEngine
from tvl_cli.agent.perception import Perception
from tvl_cli.agent.policy import Decision, Observation
from tvl_cli.core.errors import BadInput
from tvl_cli.core.method import Method
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.gym.actions import CONTINUOUS, DISCRETE
from tvl_cli.gym.task import AVOID, GOAL, RobotTask, observation_of
from tvl_cli.sim.worldmap import WorldMap

Act = Callable[[np.ndarray], Any]
# How a Stable-Baselines3 model is installed, for the error when it is not.
SB3_EXTRA = "pip install 'tvl[rl]'"


def is_model_spec(spec: str) -> bool:
    """Whether a controller is a saved Stable-Baselines3 model (ALGORITHM:FILE.zip)."""
    return spec.endswith(".zip")


@dataclass(frozen=True, slots=True)
class LoadedController:
    """A maker of the controller's action function, one for each run, and the shape of what
    it observes when it was made for one (a saved model: the observation it learnt on)."""

    make: Callable[[], Act]
    observation_shape: tuple[int, ...] | None = None  # None: whatever it is given

    def observes(
        self, world: WorldMap, goal_xy: tuple[float, float] | None, observe: Method
    ) -> bool:
        """Whether it can act on what a run of `world` observes, seeking `goal_xy` or not: a
        model learnt on avoiding (16 ranges) cannot read a goal's bearing and distance too."""
        if self.observation_shape is None:
            return True
        task = RobotTask.of(
            world, GOAL if goal_xy is not None else AVOID, goal=goal_xy, method=observe
        )
        return task.observation_space().shape == self.observation_shape


def load_controller(spec: str) -> LoadedController:
    """The controller a spec names; BadInput naming the spec for one that cannot be loaded."""
    algorithm, colon, name = spec.partition(":")
    if not colon or not algorithm or not name:
        raise BadInput(
            f"--controller {spec}: a policy is MODULE:CALLABLE or FILE.py:CALLABLE, a model "
            "ALGORITHM:FILE.zip"
        )
    if is_model_spec(spec):
        return _model(spec, algorithm, Path(name))
    return _policy(spec, algorithm, name)


def _model(spec: str, algorithm: str, path: Path) -> LoadedController:
    try:
        import stable_baselines3
    except ImportError:
        raise BadInput(f"--controller {spec}: needs Stable-Baselines3 ({SB3_EXTRA})") from None
    kind = getattr(stable_baselines3, algorithm, None)
    if not isinstance(kind, type) or not hasattr(kind, "load"):
        raise BadInput(f"--controller {spec}: Stable-Baselines3 has no algorithm {algorithm!r}")
    if not path.is_file():
        raise BadInput(f"--controller {spec}: no such file {path}")
    try:
        model = kind.load(path, device="cpu")
    except Exception as error:  # whatever the file holds instead of a model of that kind
        raise BadInput(f"--controller {spec}: not a {algorithm} model ({error})") from None

    def act(observation: np.ndarray) -> Any:
        return model.predict(observation, deterministic=True)[0]

    return LoadedController(lambda: act, tuple(model.observation_space.shape))


def _policy(spec: str, module_name: str, attribute: str) -> LoadedController:
    try:
        module = _module(module_name)
    except Exception as error:  # an import that fails is the user's module's fault
        raise BadInput(f"--controller {spec}: cannot import {module_name} ({error})") from None
    found: Any = module
    for part in attribute.split("."):
        found = getattr(found, part, None)
    if not callable(found):
        raise BadInput(f"--controller {spec}: {module_name} has no callable {attribute!r}")
    if isinstance(found, type):
        return LoadedController(found)  # a new instance for each run
    policy: Act = found

    def fresh() -> Act:
        reset = getattr(policy, "reset", None)
        if callable(reset):
            reset()
        return policy

    return LoadedController(fresh)


def _module(name: str) -> Any:
    """A module by its import name, or from a Python file (FILE.py)."""
    if not name.endswith(".py"):
        return importlib.import_module(name)
    path = Path(name).absolute()
    key = f"tvl_controller_{abs(hash(str(path)))}"
    if key in sys.modules:
        return sys.modules[key]
    found = importlib.util.spec_from_file_location(key, path)
    if found is None or found.loader is None or not path.is_file():
        raise FileNotFoundError(f"no such file {path}")
    module = importlib.util.module_from_spec(found)
    sys.modules[key] = module
    found.loader.exec_module(module)
    return module


class ControllerPolicy:
    """An action function acting on what the environment observes, as a drive-loop policy:
    each step it perceives the ring as the environment would (its method's memory), and its
    action is the command the environment would hold for the step."""

    def __init__(self, act: Act, world: WorldMap, goal_xy: tuple[float, float] | None,
                 observe: Method) -> None:  # fmt: skip
        task = GOAL if goal_xy is not None else AVOID
        self._tasks = {
            kind: RobotTask.of(world, task, goal=goal_xy, method=observe, action_type=kind)
            for kind in (DISCRETE, CONTINUOUS)
        }
        self._act = act
        self._perception = Perception(
            observe.memory, self._tasks[DISCRETE].robot, seeking_goal=goal_xy is not None
        )

    @property
    def task(self) -> RobotTask:
        return self._tasks[DISCRETE]

    def decide(self, obs: Observation) -> Decision:
        perceived = self._perception.sense(obs.time_s, obs.odometry, obs.ring_m, obs.goal_xy)
        action = self._act(observation_of(self.task, perceived, obs.odometry))
        discrete = np.ndim(action) == 0
        task = self._tasks[DISCRETE if discrete else CONTINUOUS]
        try:
            command = task.actions.command(action)
        except (TypeError, ValueError) as problem:
            raise BadInput(f"controller: {problem}") from None
        trajectories = len(task.robot.trajectories)
        index = task.actions.index(action) if discrete else -1
        return Decision(command, trajectory=index if 0 <= index < trajectories else -1)

    def interrupt(self) -> None:
        """Nothing is planned ahead: each step's action is the controller's."""


def score_controller(
    act: Act,
    world: WorldMap,
    goal_xy: tuple[float, float] | None,
    observe: Method,
    *,
    minutes: float,
    seed: int,
) -> RunMetrics:
    """One run of the controller from the world's start, seeking `goal_xy` if given, else
    avoiding; the simulator's generator seeded with `seed` as `tvl run` seeds its own."""
    policy = ControllerPolicy(act, world, goal_xy, observe)
    engine = StepEngine(world, policy.task.robot, goal_xy=goal_xy, measure=True)
    engine.reset(seed)
    return drive_engine(engine, policy, minutes)
