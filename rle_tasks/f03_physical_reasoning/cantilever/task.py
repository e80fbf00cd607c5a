"""TaskSpec of ``03-cantilever``: the longest stable overhang of four blocks beyond the table edge."""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.task import TaskSpec

from ..constants import CANTILEVER_ID
from ..task import current_secret, tabletop_task
from .scoring import RUBRIC
from .verifier import instance

HERE = Path(__file__).resolve().parent


def task_spec() -> TaskSpec:
    return tabletop_task(
        CANTILEVER_ID,
        "Tabletop physical reasoning: maximise the overhang of four blocks",
        HERE,
        RUBRIC.markdown_table(),
        lambda: instance(current_secret()).pieces,
        ("reference", "baseline/overreach", "baseline/unsealed"),
        "rle_tasks.f03_physical_reasoning.solutions.cantilever",
    )
