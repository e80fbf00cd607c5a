"""Family 07: contact-rich bin clearing (``07-bin-clearing``)."""

from __future__ import annotations

from rle_tasks.core.task import TaskSpec


def tasks() -> list[TaskSpec]:
    from rle_tasks.f07_bin_clearing.task import task_spec

    return [task_spec()]
