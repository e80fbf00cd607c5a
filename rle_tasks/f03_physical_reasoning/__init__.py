"""Family 03: tabletop physical reasoning (``03-tower``, ``03-cantilever``, ...).

Each task is a subpackage shaped like a family (``task.py``, ``scoring.py``, ``verifier.py``,
``instruction.md``, optional ``env.py`` / ``scene.py``) over the family's shared ledger gate
(``session``), tabletop scene (``scene``) and card numbers (``constants``); ``TASK_MODULES`` lists
them, so adding a task is one line here. Ids not yet implemented stay registry placeholders.
"""

from __future__ import annotations

from importlib import import_module

from rle_tasks.core.task import TaskSpec

TASK_MODULES: tuple[str, ...] = ("tower", "cantilever", "balance", "cube", "hidden_com")
"""Task subpackages, relative to this package (``cube`` is ``03-pocket-cube``)."""


def tasks() -> list[TaskSpec]:
    return [import_module(f"{__name__}.{name}.task").task_spec() for name in TASK_MODULES]
