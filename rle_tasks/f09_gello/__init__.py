"""Family 09: multi-robot GELLO gravity-compensation co-design (``09-gello``)."""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.task import TaskSpec

HERE = Path(__file__).resolve().parent


def tasks() -> list[TaskSpec]:
    from rle_tasks.f09_gello.task import task_spec

    return [task_spec()]
