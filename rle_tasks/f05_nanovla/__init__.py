"""Family 05: nanoVLA recipe engineering. ``05-libero-open`` and ``05-libero-robust`` are implemented;
the RoboTwin stand-in tracks stay placeholders (see the family README)."""

from __future__ import annotations

from rle_tasks.core.task import TaskSpec


def tasks() -> list[TaskSpec]:
    from rle_tasks.f05_nanovla.task import task_specs

    return task_specs()
