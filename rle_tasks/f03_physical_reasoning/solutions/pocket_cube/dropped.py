"""Baseline of ``03-pocket-cube``: the right hand sweeps the cube off its stand and leaves it on the table.

The right tool site comes down beside the cube (+x side, at the height of the cube's centre) and sweeps
through it towards -x; the cube falls onto the table and the arm withdraws. The verifier names the
cube resting on the table (not held) and its unsolved faces; score 0. Public geometry only: the stand
at the origin, its top at z = 0.81 m, the 64 mm cube on it.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rle_design.control import CartesianHelper

from ...cube.env import ARM_ACTION

CUBE_Z = 0.842
"""Height of the resting cube's centre [m] (stand top 0.81 m + 32 mm)."""


def solve(env: Any) -> None:
    right = CartesianHelper(env.step, env.reset(), arm=1, n_arms=2, arm_size=ARM_ACTION)
    right.move_to(np.array([0.12, 0.0, 1.0]), tol_pos=0.01)
    right.move_to(np.array([0.12, 0.0, CUBE_Z]), tol_pos=0.005)
    right.move_to(np.array([-0.12, 0.0, CUBE_Z]), tol_pos=0.01, max_steps=60)
    right.move_to(np.array([0.12, 0.0, 1.05]), tol_pos=0.01)
    right.wait(40)
