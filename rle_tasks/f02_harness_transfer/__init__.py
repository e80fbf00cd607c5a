"""Family 02: RoboCasa harness transfer (fifteen activity groups, ``02-group-01`` ... ``02-group-15``)."""

from __future__ import annotations

from rle_tasks.core.task import TaskSpec


def tasks() -> list[TaskSpec]:
    from .task import task_specs

    return task_specs()


def stage_task(task_id: str) -> TaskSpec | None:
    """A fresh agent of a group's transfer evaluation as a task of its own (``02-group-NN-fresh-K``)."""
    from .fresh import stage_task as fresh

    return fresh(task_id)


def commands() -> tuple:
    """``rle transfer-trials GROUP SUBMISSION --agent AGENT``: the five fresh agents as Harbor trials."""
    from .harbor_trials import add_parser

    return (add_parser,)
