"""Baseline of ``03-pocket-cube``: both arms hold for a second, then the session is sealed.

The cube stays scrambled on its stand: the verifier names the non-uniform faces and the cube resting
on its stand (not held); score 0.
"""

from __future__ import annotations

from typing import Any

from rle_design.control import CartesianHelper

from ...cube.env import ARM_ACTION


def solve(env: Any, actions: int = 20) -> None:
    helper = CartesianHelper(env.step, env.reset(), n_arms=2, arm_size=ARM_ACTION)
    helper.wait(actions)
