"""Reference agent of ``03-balance-coins``: a ternary search in two weighings, read off the pans.

Runs against anything with ``reset()``, ``step(action)`` and ``observe()`` (the workspace's
``client.connect()``, or a ``MeteredSession`` in tests); every motion is an ordinary metered action
sent through ``rle_design.control.CartesianHelper``. It reads only what the card exposes: cube
centres and pan positions (``balance``) and the arm's state; no mass, no privileged pose.

Strategy (ceil(log3 9) = 2 weighings):

1. cubes 0, 1, 2 on the left pan, 3, 4, 5 on the right; weigh;
2. balanced: the heavy cube is 6, 7 or 8: add 6 to the left and 7 to the right; weigh;
   otherwise the lower pan holds three candidates (a, b, c) and the other three known light cubes
   (x, y, z): c and z back to the table, b to the light pan, y to the candidates' pan; weigh
   {a, y} against {x, b};
3. the lower pan names the cube (balanced: the one left out); it goes onto the mat.

A weighing releases the beam for ``WEIGH_ACTIONS`` actions (mode > 0.5) with the arm parked above,
then compares the pans' heights (``TILT_Z`` apart at least).

Run it in a workspace with ``python reference.py`` (it connects, solves and seals).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from rle_design.control import CartesianHelper
from rle_design.control.layout import ACTION_SIZE, GRIPPER, MODE

SLOTS = (-0.06, -0.02, 0.02, 0.06)
"""Cube places on a tray along world x, from its centre [m]."""
WEIGH_ACTIONS = 160
"""Release actions per weighing (3.2 s; the beam settles within 3 s)."""
TILT_Z = 0.005
"""Pan height difference that counts as a tilt [m] (the lightest instance tilts the pans by ~40 mm)."""
HALF = 0.015
"""Half a cube [m]."""
TRAVEL_Z = 1.0
"""Height of every carry [m]: a held cube clears the beam (0.91 m) and cubes on a raised pan."""
PARK = np.array([0.15, 0.0, 1.05])
"""Where the hand waits during a weighing [m]."""
DOWN = np.array([0.0, 0.70710678, 0.70710678, 0.0])
"""Tool pointing down, fingers closing along world y (w, x, y, z)."""


class Agent:
    """Pick-and-place and weighings on one session (see the module docstring)."""

    def __init__(self, env: Any) -> None:
        self.env = env
        obs = env.reset()
        self.helper = CartesianHelper(env.step, obs)
        self.home = np.array(obs["balance"]["cubes"])  # table places, also where cubes go back

    @property
    def balance(self) -> dict[str, Any]:
        return self.helper.obs["balance"]

    def _move(self, pos: np.ndarray, speed: float = 1.0, tol: float = 0.003) -> None:
        self.helper.move_to(np.asarray(pos, dtype=float), DOWN, speed=speed, tol_pos=tol, max_steps=300)

    def _slot(self, pan: int, slot: int) -> np.ndarray:
        return np.asarray(self.balance["pans"][pan], dtype=float) + np.array([SLOTS[slot], 0.0, HALF])

    def move_cube(self, cube: int, dest: np.ndarray) -> None:
        """Pick ``cube`` where it is now and set it down with its centre at ``dest`` [m]."""
        src = np.asarray(self.balance["cubes"][cube], dtype=float)
        self._move([*src[:2], TRAVEL_Z])
        self._move(src, speed=0.5, tol=0.004)
        self.helper.grasp(12)
        self._move([*src[:2], TRAVEL_Z])
        self._move([*dest[:2], TRAVEL_Z])
        self._move(dest + [0, 0, 0.012], speed=0.5, tol=0.004)
        self.helper.release(8)
        self._move([*dest[:2], TRAVEL_Z])

    def to_pan(self, cube: int, pan: int, slot: int) -> None:
        self.move_cube(cube, self._slot(pan, slot))

    def to_table(self, cube: int) -> None:
        self.move_cube(cube, self.home[cube])

    def weigh(self) -> int:
        """One weighing; returns -1 (left pan lower), +1 (right pan lower) or 0 (level)."""
        self._move(PARK)
        action = np.zeros(ACTION_SIZE)
        action[GRIPPER] = self.helper.grip
        action[MODE] = 1.0
        for _ in range(WEIGH_ACTIONS):
            self.helper.obs = self.env.step(action)
        dz = float(self.balance["pans"][0][2] - self.balance["pans"][1][2])
        action[MODE] = 0.0
        self.helper.obs = self.env.step(action)  # lock at the settled angle
        return 0 if abs(dz) < TILT_Z else (-1 if dz < 0 else 1)

    def to_mat(self, cube: int, mat: np.ndarray) -> None:
        self.move_cube(cube, mat)
        self._move(PARK)


def solve(env: Any, *, extra_weighings: int = 0, choose: Callable[[int], int] = lambda heavy: heavy) -> int:
    """Find the heavy cube in two weighings and put it on the mat.

    Args:
        env: The session (``reset``, ``step``, ``observe``).
        extra_weighings: Repeats of the first weighing (baselines only).
        choose: Maps the cube found to the cube put on the mat (baselines only).

    Returns:
        The cube put on the mat.
    """
    agent = Agent(env)
    for i in range(3):
        agent.to_pan(i, 0, i)
        agent.to_pan(3 + i, 1, i)
    first = agent.weigh()
    for _ in range(extra_weighings):
        agent.weigh()
    if first == 0:
        agent.to_pan(6, 0, 3)
        agent.to_pan(7, 1, 3)
        second = agent.weigh()
        heavy = {-1: 6, 1: 7, 0: 8}[second]
    else:
        cand_pan = 0 if first < 0 else 1
        cands = [0, 1, 2] if cand_pan == 0 else [3, 4, 5]
        lights = [3, 4, 5] if cand_pan == 0 else [0, 1, 2]
        a, b, c = cands
        x, y, z = lights
        agent.to_table(c)
        agent.to_table(z)
        agent.to_pan(b, 1 - cand_pan, 2)
        agent.to_pan(y, cand_pan, 2)
        second = agent.weigh()
        lower = {-1: 0, 1: 1}.get(second)
        heavy = c if lower is None else (a if lower == cand_pan else b)
    chosen = choose(heavy)
    agent.to_mat(chosen, np.asarray(agent.balance["mat"], dtype=float) + [0.0, 0.0, HALF])
    return chosen


def main() -> None:
    from client import connect  # the workspace's client (written by `rle dev`)

    with connect() as env:
        print("heavy cube:", solve(env))
        env.seal()


if __name__ == "__main__":
    main()
