"""Family 03: tabletop physical reasoning (``03-tower``, ``03-cantilever``, ...).

Each task lives in its own module (or subpackage) exposing ``task_spec()``; ``TASK_MODULES`` lists
them, so adding a task is one line here. Ids not yet implemented stay registry placeholders.
"""

from __future__ import annotations

from importlib import import_module

from rle_tasks.core.task import TaskSpec

TASK_MODULES: tuple[str, ...] = ("tower", "cantilever", "balance", "cube", "hidden_com")
"""Modules of the implemented tasks, relative to this package (``cube`` is the ``03-pocket-cube``
subpackage)."""


def tasks() -> list[TaskSpec]:
    return [import_module(f"{__name__}.{name}").task_spec() for name in TASK_MODULES]
