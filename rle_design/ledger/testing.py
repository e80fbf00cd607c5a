"""Ledgers written directly with a key, for tests and the audit corpus (the stand-in for a leaked key),
and the two tampers the shipped baselines apply to a real ledger.

A real session's ledger comes from its server; ``forge_ledger`` writes any records with the right MACs
so that only the gate's recount (``rle_design.ledger.gate``) can tell what is wrong with them.
``cut_seal`` and ``flip_last_action`` damage a sealed ledger as an agent without the key could: the
verdicts are ``ledger.unsealed`` and a MAC mismatch.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any

from rle_design.ledger.records import LedgerWriter

__all__ = ["cut_seal", "flip_last_action", "forge_ledger"]


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


def cut_seal(path: Path) -> None:
    """Cut the seal (the last record) off the ledger file ``path``."""
    path = Path(path)
    lines = path.read_bytes().splitlines(keepends=True)
    path.write_bytes(b"".join(lines[:-1]))


def flip_last_action(path: Path) -> None:
    """Flip one hex digit of the last recorded action of the ledger file ``path`` (its record's MAC no
    longer matches)."""
    path = Path(path)
    lines = path.read_bytes().splitlines(keepends=True)
    k = max(i for i, line in enumerate(lines) if b'"kind":"steps"' in line)
    line = lines[k]
    at = line.rindex(b'"]') - 1
    digit = b"1" if line[at : at + 1] != b"1" else b"2"
    lines[k] = line[:at] + digit + line[at + 1 :]
    path.write_bytes(b"".join(lines))
