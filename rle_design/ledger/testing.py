"""Ledgers written directly with a key, for tests and the audit corpus (the stand-in for a leaked key).

A real session's ledger comes from its server; ``forge_ledger`` writes any records with the right MACs
so that only the gate's recount (``rle_design.ledger.gate``) can tell what is wrong with them.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any

from rle_design.ledger.records import LedgerWriter

__all__ = ["forge_ledger"]


def forge_ledger(
    path: Path,
    key: bytes,
    task_id: str,
    meta: dict[str, Any],
    records: Iterable[tuple[str, dict[str, Any]]],
    seal: dict[str, Any] | None = None,
) -> Path:
    """Write a sealed ledger holding exactly ``records`` ((kind, payload) pairs of ``reset``/``steps``).

    The running ``steps`` counter of each payload is filled in as a server would (one per reset and per
    action) unless the payload gives its own; the seal counts the steps and adds ``seal``.
    """
    w = LedgerWriter(Path(path), key, task_id, meta)
    steps = 0
    for kind, payload in records:
        steps += len(payload.get("actions", [None])) if kind == "steps" else 1
        w.append(kind, {"steps": steps, "time": 0.0, **payload})
    w.seal(steps, seal)
    return Path(path)
