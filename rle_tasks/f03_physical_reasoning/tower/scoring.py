"""Rubric of ``03-tower``: one checkpoint, the settled height of the robot-free tower over H*.

A missing, unsealed or altered ledger (or one that does not replay) makes the report invalid with
score 0 and the ledger's reason; otherwise the score is the card's ratio clipped to [0, 1].
"""

from __future__ import annotations

from rle_tasks.core.scoring import CheckpointSpec, Fraction, Rubric

from ..constants import TOWER_ID

RUBRIC = Rubric(
    task_id=TOWER_ID,
    family="03",
    workflow="interactive_control",
    variants=("scene",),
    checkpoints=(
        CheckpointSpec(
            "height",
            1.0,
            "settled height of the robot-free tower above the table / H* [1]",
            Fraction("height / H*, clipped to [0, 1]"),
        ),
    ),
)
RUBRICS = {TOWER_ID: RUBRIC}
