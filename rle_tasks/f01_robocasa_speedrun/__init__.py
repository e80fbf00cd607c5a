"""Family 01: RoboCasa speed-run (five kitchen tasks x harness levels L1-L3, ``01-<task>-l<level>``)."""

from __future__ import annotations

from rle_tasks.core.task import TaskSpec


def tasks() -> list[TaskSpec]:
    from .task import task_specs

    return task_specs()
