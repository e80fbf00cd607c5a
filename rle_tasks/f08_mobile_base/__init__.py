"""Family 08: universal mobile-manipulator base (``08-mobile-base``)."""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.task import TaskSpec

HERE = Path(__file__).resolve().parent


def tasks() -> list[TaskSpec]:
    from rle_tasks.f08_mobile_base.task import task_spec

    return [task_spec()]
