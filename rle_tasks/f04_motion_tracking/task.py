"""TaskSpecs of family 04 (registered once a reference policy ships; until then the placeholders stay)."""

from __future__ import annotations

from rle_tasks.core.task import TaskSpec


def task_specs() -> list[TaskSpec]:
    return []
