"""Rubric of ``03-balance-coins``: one checkpoint, the heavy cube alone on the mat, weighings counted."""

from __future__ import annotations

from ..constants import BALANCE_ID
from ..rubric import ledger_rubric

OPTIMAL_WEIGHINGS = 2
"""ceil(log3 9): the fewest weighings that always find the heavy cube."""

RUBRIC = ledger_rubric(
    BALANCE_ID,
    "scene",
    "identified",
    "only the heavy cube rests on the mat after robot-free settling; w = weighings in the ledger",
    "0 unless only the heavy cube is on the mat; then 1 for w <= 2, else 2/w",
)
RUBRICS = {BALANCE_ID: RUBRIC}


def weighing_score(heavy_only: bool, weighings: int) -> float:
    """The card's score: 0 unless only the heavy cube reached the mat; then 1 for w <= 2, else 2/w."""
    if not heavy_only:
        return 0.0
    return 1.0 if weighings <= OPTIMAL_WEIGHINGS else OPTIMAL_WEIGHINGS / weighings
