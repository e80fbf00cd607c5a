"""TaskSpec of ``03-tower``: build the tallest stable robot-free tower from twelve mixed pieces."""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.task import TaskSpec

from ..constants import TOWER_ID
from ..task import current_secret, tabletop_task
from .scoring import RUBRIC
from .verifier import instance

HERE = Path(__file__).resolve().parent


def task_spec() -> TaskSpec:
    return tabletop_task(
        TOWER_ID,
        "Tabletop physical reasoning: build a stable tower from 12 mixed pieces",
        HERE,
        RUBRIC.markdown_table(),
        lambda: instance(current_secret()).pieces,
        ("reference", "baseline/knocked_over", "baseline/unsealed"),
        "rle_tasks.f03_physical_reasoning.solutions.tower",
    )
