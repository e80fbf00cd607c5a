"""Rubric of ``03-hidden-com``: one checkpoint, the fraction of the three answers that are right."""

from __future__ import annotations

from ..constants import HIDDEN_COM_ID
from ..rubric import ledger_rubric

RUBRIC = ledger_rubric(
    HIDDEN_COM_ID,
    "boxes",
    "answers",
    "answers naming the ballast quadrant, out of three boxes (first valid answer per box)",
    "fraction of the three answers correct",
)
RUBRICS = {HIDDEN_COM_ID: RUBRIC}
