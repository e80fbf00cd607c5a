"""Rubric of ``03-cantilever``: one checkpoint, the settled overhang over the Paterson-Zwick optimum.

A missing, unsealed or altered ledger (or one that does not replay) makes the report invalid with
score 0 and the ledger's reason; otherwise the score is the card's ratio clipped to [0, 1].
"""

from __future__ import annotations

import math

from ..constants import CANTILEVER_ID
from ..rubric import ledger_rubric

PZ4 = (15.0 - 4.0 * math.sqrt(2.0)) / 8.0
"""Paterson-Zwick optimal overhang of four blocks, in block lengths (1.16789)."""

RUBRIC = ledger_rubric(
    CANTILEVER_ID,
    "scene",
    "overhang",
    "settled overhang beyond the table edge along its normal / ((15 - 4 sqrt 2)/8 L) [1]",
    "overhang / (1.16789 L), clipped to [0, 1]",
)
RUBRICS = {CANTILEVER_ID: RUBRIC}
