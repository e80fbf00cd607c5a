"""Baseline of ``03-balance-coins``: the reference, repeating its first weighing three times.

Finds and places the right cube after five weighings: scores 2/5 = 0.4 (the card's 2/w).
"""

from __future__ import annotations

from typing import Any

from .reference import solve as _solve


def solve(env: Any) -> int:
    return _solve(env, extra_weighings=3)
