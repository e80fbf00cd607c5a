"""Rubric of ``03-hidden-com``: one checkpoint, the fraction of the three answers that are right."""

from __future__ import annotations

from rle_tasks.core.scoring import CheckpointSpec, Fraction, Rubric

from ..constants import HIDDEN_COM_ID

RUBRIC = Rubric(
    task_id=HIDDEN_COM_ID,
    family="03",
    workflow="interactive_control",
    variants=("boxes",),
    checkpoints=(
        CheckpointSpec(
            "answers",
            1.0,
            "answers naming the ballast quadrant, out of three boxes (first valid answer per box)",
            Fraction("fraction of the three answers correct"),
        ),
    ),
)
RUBRICS = {HIDDEN_COM_ID: RUBRIC}
