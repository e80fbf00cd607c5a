"""The ledger of a served development session: every request a record, the budget per attempt.

A served development environment (a renderer, an evaluation server) answers requests rather than
stepping a simulator. ``ServedLedger`` is what such a server writes: one ``request`` record per
request, free ones included (``cost`` 0), with its arguments, the digest of the submission it ran
on, what it returned that an auditor needs (a design-set score, episode outcomes) and its wall
stamp; the seal closes it. The budget the card meters belongs to the attempt, not to the process:
a session opened in an attempt that had sessions before (the ledgers ``<attempt>-session-*.jsonl``
beside its own) starts with what they spent, counted from their authentic records, so restarting the
server gives nothing back. The open record states the budget and what earlier sessions spent.
"""

from __future__ import annotations

import hmac
import json
import math
import re
import time
from pathlib import Path
from typing import Any

from rle_design.ledger.records import LedgerError, LedgerWriter, mac_input

__all__ = ["ServedLedger", "spent_by_attempt"]

_MAC_TAIL = re.compile(rb',"mac":"([0-9a-f]{64})"\}$')


def _spent(path: Path, key: bytes, task_id: str) -> int:
    """Units charged by the authentic records of one ledger (sealed or not) [budget units]."""
    spent = 0
    try:
        lines = path.read_bytes().splitlines()
    except OSError:
        return 0
    for raw in lines:
        m = _MAC_TAIL.search(raw)
        if m is None or not hmac.compare_digest(
            hmac.digest(key, mac_input(raw), "sha256").hex(), m.group(1).decode()
        ):
            continue
        try:
            rec = json.loads(raw)
        except ValueError:
            continue
        steps = rec.get("payload", {}).get("steps") if isinstance(rec, dict) else None
        if rec.get("task_id") == task_id and isinstance(steps, int) and not isinstance(steps, bool):
            spent = max(spent, steps)
    return spent


def spent_by_attempt(
    directory: Path, attempt: str, key: bytes, task_id: str, exclude: Path | None = None
) -> tuple[list[str], int]:
    """(names, units) of the earlier sessions of ``attempt`` in ``directory``: what their authentic
    records charged (an unsealed ledger of a killed server counts what it recorded)."""
    if not attempt:
        return [], 0
    names, total = [], 0
    for path in sorted(Path(directory).glob(f"{attempt}-session-*.jsonl")):
        if exclude is not None and path.resolve() == Path(exclude).resolve():
            continue
        names.append(path.name)
        total += _spent(path, key, task_id)
    return names, total


class ServedLedger:
    """The sealed record of one served session (see the module docstring).

    Args:
        path: The new ledger file.
        key: Ledger key.
        task_id: The task.
        budget: Charged units the attempt may spend (evaluations, episodes).
        unit: What one unit is, in words (``"evaluations"``, ``"episodes"``).
        attempt: The attempt the session belongs to ("" counts no earlier sessions).
        meta: Further fields of the open record.
    """

    def __init__(
        self,
        path: Path,
        key: bytes,
        task_id: str,
        *,
        budget: int,
        unit: str,
        attempt: str = "",
        meta: dict[str, Any] | None = None,
    ) -> None:
        path = Path(path)
        self.sessions, self.previous = spent_by_attempt(path.parent, attempt, key, task_id, exclude=path)
        self.budget, self.unit, self.used = int(budget), unit, 0
        self._t0 = time.monotonic()
        self.writer = LedgerWriter(
            path,
            key,
            task_id,
            {
                **(meta or {}),
                "attempt": attempt,
                "budget": self.budget,
                "unit": unit,
                "previous": {"sessions": self.sessions, "used": self.previous},
            },
        )

    @property
    def left(self) -> int:
        """Units the attempt has left."""
        return self.budget - self.previous - self.used

    @property
    def sealed(self) -> bool:
        return self.writer.sealed

    def _wall(self) -> float:
        return math.floor((time.monotonic() - self._t0) * 1000.0) / 1000.0

    def check(self, cost: int) -> None:
        """Refuse a request of ``cost`` units the attempt cannot pay (nothing is recorded).

        Raises:
            LedgerError: ``ledger.budget_exhausted``, ``ledger.sealed``.
        """
        if self.sealed:
            raise LedgerError("the session is sealed", code="ledger.sealed")
        if cost > self.left:
            spent = self.previous + self.used
            earlier = f" ({self.previous} by earlier sessions of this attempt)" if self.previous else ""
            raise LedgerError(
                f"{cost} {self.unit} requested, {self.left} of the attempt's {self.budget} left: {spent} used{earlier}",
                code="ledger.budget_exhausted",
            )

    def record(self, op: str, args: dict[str, Any], cost: int = 0, **result: Any) -> None:
        """Write one request (``cost`` units, checked with ``check`` first by the caller) and flush."""
        if self.sealed:
            raise LedgerError("the session is sealed", code="ledger.sealed")
        self.used += int(cost)
        self.writer.append(
            "request",
            {**result, "op": op, "args": args, "cost": int(cost), "steps": self.used, "wall": self._wall()},
        )
        self.writer.flush()

    def info(self) -> dict[str, Any]:
        """Budget of the attempt in numbers (free)."""
        return {
            f"{self.unit}_used": self.previous + self.used,
            f"{self.unit}_left": self.left,
            f"{self.unit}_this_session": self.used,
            "budget": self.budget,
        }

    def seal(self) -> None:
        """Seal (idempotent)."""
        if not self.sealed:
            self.writer.seal(
                self.used,
                {"elapsed_s": round(time.monotonic() - self._t0, 3), "previous_used": self.previous},
            )
