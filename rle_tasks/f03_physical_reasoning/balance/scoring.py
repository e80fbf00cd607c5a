"""Rubric of ``03-balance-coins``: one checkpoint, the heavy cube alone on the mat, weighings counted."""

from __future__ import annotations

from rle_tasks.core.scoring import CheckpointSpec, Fraction, Rubric

from ..constants import BALANCE_ID

OPTIMAL_WEIGHINGS = 2
"""ceil(log3 9): the fewest weighings that always find the heavy cube."""

RUBRIC = Rubric(
    task_id=BALANCE_ID,
    family="03",
    workflow="interactive_control",
    variants=("scene",),
    checkpoints=(
        CheckpointSpec(
            "identified",
            1.0,
            "only the heavy cube rests on the mat after robot-free settling; w = weighings in the ledger",
            Fraction("0 unless only the heavy cube is on the mat; then 1 for w <= 2, else 2/w"),
        ),
    ),
)
RUBRICS = {BALANCE_ID: RUBRIC}


def weighing_score(heavy_only: bool, weighings: int) -> float:
    """The card's score: 0 unless only the heavy cube reached the mat; then 1 for w <= 2, else 2/w."""
    if not heavy_only:
        return 0.0
    return 1.0 if weighings <= OPTIMAL_WEIGHINGS else OPTIMAL_WEIGHINGS / weighings
