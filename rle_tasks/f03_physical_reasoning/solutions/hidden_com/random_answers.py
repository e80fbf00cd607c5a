"""Baseline of ``03-hidden-com``: answers each box with a seeded random quadrant, without probing.

Expected score 1/4 over instances; for a given seed and instance the score is the count of lucky
guesses / 3 (the test computes it from the instance it knows).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .reference import BOX_CODES, QUADRANT_CODES


def guesses(seed: int) -> tuple[str, ...]:
    rng = np.random.default_rng(seed)
    return tuple(str(q) for q in rng.choice(list(QUADRANT_CODES), size=3))


def solve(env: Any, seed: int = 0) -> tuple[str, ...]:
    env.reset()
    answers = guesses(seed)
    for box, quad in enumerate(answers):
        a = np.zeros(12)
        a[6] = -1.0
        a[11] = 1.0
        a[7] = BOX_CODES[box]
        a[10] = QUADRANT_CODES[quad]
        env.step(a)
    return answers
