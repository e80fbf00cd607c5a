"""Family 06: blind planar pose estimation (``06-pose-a-rgb`` ... ``06-pose-d-agnostic``)."""

from __future__ import annotations

from rle_tasks.core.task import TaskSpec


def tasks() -> list[TaskSpec]:
    from rle_tasks.f06_pose_estimation.task import task_specs

    return task_specs()
