"""The adversarial artifact corpus: each case builds one bad artifact and names the error code it must
produce and the highest score it may get.

This package holds what no family owns: the ledger-format cases (``ledger_cases.py``), the builders
(``artifacts.py``), and the generic case lists a family applies to its own submission (``xml_cases``
for a submitted MJCF, ``code_cases`` for submitted code, ``generated`` additions, ``ledger_limits``
for a metered session). Each family keeps its cases, and their score bounds, beside its tasks
(``rle_tasks/<family>/audit.py``: ``cases()``), discovered here like the tasks are.
"""

from __future__ import annotations

import importlib
import pkgutil

import rle_tasks
from rle_tasks.audit.case import Case
from rle_tasks.audit.ledger_cases import ledger_cases

__all__ = ["cases", "family_cases"]


def cases() -> list[Case]:
    """Every case: the ledger-format ones, then each family's."""
    return ledger_cases() + family_cases()


def family_cases() -> list[Case]:
    """The cases each family keeps beside its tasks (``rle_tasks/<family>/audit.py``: ``cases()``)."""
    out: list[Case] = []
    for mod in sorted(m.name for m in pkgutil.iter_modules(rle_tasks.__path__) if m.name[:1] == "f"):
        if importlib.util.find_spec(f"rle_tasks.{mod}.audit") is not None:
            out += importlib.import_module(f"rle_tasks.{mod}.audit").cases()
    return out
