"""Baseline of ``03-balance-coins``: weighs like the reference, then puts a light cube on the mat (score 0)."""

from __future__ import annotations

from typing import Any

from .reference import solve as _solve


def solve(env: Any) -> int:
    return _solve(env, choose=lambda heavy: (heavy + 1) % 9)
