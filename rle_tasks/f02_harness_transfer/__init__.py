"""Family 02: RoboCasa harness transfer (fifteen activity groups, ``02-group-01`` ... ``02-group-15``)."""

from __future__ import annotations

from rle_tasks.core.task import TaskSpec


def tasks() -> list[TaskSpec]:
    from .task import task_specs

    return task_specs()
