"""Reference agent programs of family 01 (build time): one ``solve(robot, motion)`` per kitchen task.

A program plays one episode from the observation after a reset and returns when the task's success
predicate holds (``obs["success"]``) or it gives up. ``play`` is a whole session as an agent would run
it: a short development phase on pretrain kitchens, then the evaluation phase, one episode per trial.
The programs read the level-3 observation (world-frame poses) through the workspace harness
(``rle_tasks.envs.kitchen.harness``), exactly the modules an L3 agent gets.
"""

from __future__ import annotations

from collections.abc import Callable
from importlib import import_module
from typing import Any

from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot

__all__ = ["PROGRAMS", "Direct", "available", "play", "solver"]

PROGRAMS: dict[str, str] = {
    "OpenFridge": "open_fridge",
    "CloseCabinet": "close_cabinet",
    "TurnOnStove": "turn_on_stove",
    "PickPlaceCounterToDrawer": "pnp_counter_to_drawer",
    "PickPlaceMicrowaveToCounter": "pnp_microwave_to_counter",
}
"""Kitchen task -> module of its program in this package."""


def solver(task: str, level: int = 3) -> Callable[[Robot, Motion], bool]:
    """The ``solve(robot, motion) -> bool`` of a kitchen task at a harness level: module
    ``<program>_l<level>`` for levels 1 and 2, ``<program>`` (the L3 program) for level 3.

    Raises:
        ModuleNotFoundError: No program for that level.
    """
    name = PROGRAMS[task] if level == 3 else f"{PROGRAMS[task]}_l{level}"
    return import_module(f"{__name__}.{name}").solve


def available(task: str, level: int) -> bool:
    """Whether a program exists for ``task`` at ``level``."""
    from importlib.util import find_spec

    name = PROGRAMS[task] if level == 3 else f"{PROGRAMS[task]}_l{level}"
    return find_spec(f"{__name__}.{name}") is not None


class Direct:
    """A ``LedgerClient`` look-alike over an in-process session (development of the programs, tests)."""

    def __init__(self, session: Any) -> None:
        self.session = session

    def reset(self, **options: Any) -> dict[str, Any]:
        return self.session.reset(options or None)

    def step(self, action: Any) -> dict[str, Any]:
        return self.session.step(action)

    def observe(self) -> dict[str, Any]:
        return self.session.observe()

    def query(self, name: str, **args: Any) -> Any:
        return self.session.query(name, args)

    def info(self) -> dict[str, Any]:
        return self.session.info()


def play(client: Any, task: str, level: int = 3, *, dev_episodes: int = 1, trials: int = 5) -> list[bool]:
    """A session: ``dev_episodes`` pretrain episodes, then every evaluation trial; returns the trials'
    success as the program saw it."""
    solve = solver(task, level)
    robot = Robot(client)
    motion = Motion(robot)
    for k in range(dev_episodes):
        robot.reset(kitchen=k, seed=k)
        solve(robot, motion)
    out = []
    for k in range(trials):
        if k == 0:
            robot.start_evaluation()
        else:
            robot.reset()
        out.append(bool(solve(robot, motion)))
    return out
