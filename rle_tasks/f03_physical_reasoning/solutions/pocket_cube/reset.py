"""Baseline of ``03-pocket-cube``: a reset after the start, which abandons the attempt (score 0)."""

from __future__ import annotations

from typing import Any

from rle_design.control import CartesianHelper

from ...cube.env import ARM_ACTION


def solve(env: Any) -> None:
    helper = CartesianHelper(env.step, env.reset(), n_arms=2, arm_size=ARM_ACTION)
    helper.wait(5)
    helper = CartesianHelper(env.step, env.reset(), n_arms=2, arm_size=ARM_ACTION)
    helper.wait(5)
