"""Rubric of ``03-tower``: one checkpoint, the settled height of the robot-free tower over H*.

A missing, unsealed or altered ledger (or one that does not replay) makes the report invalid with
score 0 and the ledger's reason; otherwise the score is the card's ratio clipped to [0, 1].
"""

from __future__ import annotations

from ..constants import TOWER_ID
from ..rubric import ledger_rubric

RUBRIC = ledger_rubric(
    TOWER_ID,
    "scene",
    "height",
    "settled height of the robot-free tower above the table / H* [1]",
    "height / H*, clipped to [0, 1]",
)
RUBRICS = {TOWER_ID: RUBRIC}
