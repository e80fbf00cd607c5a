"""Reference agent programs of family 01 (build time): one ``solve(robot, motion)`` per kitchen task.

A program plays one episode from the observation after a reset and returns when the task's success
predicate holds (``obs["success"]``) or it gives up. ``play`` is a whole session as an agent would run
it: a short development phase on pretrain kitchens, then the evaluation phase, one episode per trial.
The programs use the workspace harness (``rle_tasks.envs.kitchen.harness``), exactly the modules an
agent of their level gets: the L3 programs read world-frame poses (``world``), the L2 programs only
images, depth, camera geometry and the ``segment`` query. A program of a level also runs at the
levels above it. ``play`` serves them observations turned into the frame of the run the robot starts
facing (``frame``), so they work in every layout kind as written for the one-wall kitchen.
"""

from __future__ import annotations

from collections.abc import Callable
from importlib import import_module
from typing import Any

from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot

from .frame import Straightened

__all__ = ["PROGRAMS", "PROGRAMS_BY_LEVEL", "Direct", "available", "play", "solver"]

PROGRAMS: dict[str, str] = {
    "OpenFridge": "open_fridge",
    "CloseCabinet": "close_cabinet",
    "TurnOnStove": "turn_on_stove",
    "PickPlaceCounterToDrawer": "pnp_counter_to_drawer",
    "PickPlaceMicrowaveToCounter": "pnp_microwave_to_counter",
}
"""Kitchen task -> module of its L3 program in this package."""
PROGRAMS_BY_LEVEL: dict[int, dict[str, str]] = {
    3: PROGRAMS,
    2: {
        "OpenFridge": "open_fridge_l2",
        "CloseCabinet": "close_cabinet_l2",
        "TurnOnStove": "turn_on_stove_l2",
        "PickPlaceCounterToDrawer": "pnp_counter_to_drawer_l2",
        "PickPlaceMicrowaveToCounter": "pnp_microwave_to_counter_l2",
    },
    1: {
        "OpenFridge": "open_fridge_l1",
        "CloseCabinet": "close_cabinet_l1",
        "TurnOnStove": "turn_on_stove_l1",
    },
}
"""Harness level -> kitchen task -> module of the program written for that level."""


def solver(task: str, level: int = 3) -> Callable[[Robot, Motion], bool]:
    """The ``solve(robot, motion) -> bool`` of a kitchen task at a harness level: the program of the
    highest level <= ``level`` that has one.

    Raises:
        KeyError: No program of the task runs at ``level``.
    """
    for lv in range(level, 0, -1):
        module = PROGRAMS_BY_LEVEL.get(lv, {}).get(task)
        if module is not None:
            return import_module(f"{__name__}.{module}").solve
    raise KeyError(f"no program of {task} runs at harness level {level}")


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


def play(client: Any, task: str, *, level: int = 3, dev_episodes: int = 1, trials: int = 5) -> list[bool]:
    """A session at harness ``level``: ``dev_episodes`` pretrain episodes, then every evaluation trial;
    returns the trials' success as the program saw it."""
    solve = solver(task, level)
    robot = Robot(Straightened(client))  # observations in the target run's frame (``frame``)
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


def available(task: str, level: int) -> bool:
    """Whether a program of ``task`` runs at harness ``level`` (and is installed)."""
    from importlib.util import find_spec

    return any(
        task in PROGRAMS_BY_LEVEL.get(lv, {})
        and find_spec(f"{__name__}.{PROGRAMS_BY_LEVEL[lv][task]}") is not None
        for lv in range(level, 0, -1)
    )
