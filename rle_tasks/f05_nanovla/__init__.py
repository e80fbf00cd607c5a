"""Family 05: nanoVLA recipe engineering. ``05-libero-open`` and ``05-libero-robust`` run on LIBERO-10
in its side environment; ``05-robotwin-open`` and ``05-robotwin-robust`` run on the bimanual stand-in
for RoboTwin 2.0 (``rle_tasks.envs.standin``; see the family README)."""

from __future__ import annotations

from rle_tasks.core.task import TaskSpec


def tasks() -> list[TaskSpec]:
    from rle_tasks.f05_nanovla.task import task_specs

    return task_specs()
