"""The ledger file: JSON lines, each record HMAC-SHA256-chained to the previous one.

A record is one line of canonical JSON with the fields, in this order::

    {"seq": 0, "kind": "open", "task_id": "08-mobile-base", "prev": "<64 hex>",
     "digest": "<64 hex>", "payload": {...}, "mac": "<64 hex>"}

- ``seq`` counts records from 0; ``kind`` is ``open`` (first record), ``reset`` (one charged step),
  ``steps`` (a group of consecutive executed actions, each one charged step), ``request`` (one
  request to a served development environment, charged ``cost`` units: 0 for a free one) or ``seal``
  (last);
- ``prev`` is SHA-256 of the previous line's bytes (64 zeros for the open record);
- ``digest`` is SHA-256 of the payload's canonical JSON (sorted keys, no spaces);
- ``mac`` is HMAC-SHA256(key, line without its ``,"mac":"..."`` member), so it covers every byte of
  every other field.

A ``steps`` record's payload is ``{"actions": [hex, ...], "steps": n, "time": t, "wall": w}``: each
action's float64 bytes in hex (native order, little-endian on x86-64 and arm64) as applied (after any
clipping to the action range), the charged steps used after the last of them, the simulation time
then [s] and the session's wall clock when the last of them was charged [s since the session opened,
floored to the millisecond]. Grouping consecutive actions in one record (group commit,
``actions_per_record``) keeps the per-action cost of the chain low; a reset or the seal always closes
the open group first. A ``reset`` payload is ``{"steps": n, "time": t, "wall": w}``.
A ``request`` payload is ``{"op": name, "args": {...}, "cost": c, "steps": n, "wall": w, ...}`` plus
what the request returned that an auditor needs (``rle_design.ledger.served``).

The open record carries the format (``FORMAT``), a random nonce and the attempt the session belongs to
(``attempt``, issued by the operator; "" when unbound); the seal records the number of records before
it, the charged step count, the head hash (``prev`` of the seal) and the ledger id (SHA-256 of the open
line), so a seal cannot be moved to another ledger. A time-limited session states its limit in the open
record (``wall_time_s``) and the wall time it used in the seal (``elapsed_s``) [s]. The key never
appears in the file. ``rle_design.ledger.gate`` re-checks every limit on these records.
"""

from __future__ import annotations

import hashlib
import json
import os
import secrets
import time
from pathlib import Path
from typing import Any

from rle_design.errors import RleError

FORMAT = 2
"""Ledger format: 2 adds the attempt to the open record and wall stamps to charged records."""
GENESIS = "0" * 64
KINDS = ("open", "reset", "steps", "request", "seal")
CHARGED = ("reset", "steps", "request")
MAC_SUFFIX_LEN = len(',"mac":""}') + 64


class LedgerError(RleError):
    """Ledger misuse or a refused metered operation (budget spent, bad action, sealed session)."""

    code = "ledger.error"


def cost(kind: str, payload: dict[str, Any]) -> int | None:
    """Charged units of a record: 1 per reset, 1 per action of a ``steps`` record, a request's
    ``cost``; None when the record does not state them in a valid form."""
    if kind == "reset":
        return 1
    if kind == "steps":
        actions = payload.get("actions")
        return len(actions) if isinstance(actions, list) and actions else None
    if kind == "request":
        c = payload.get("cost")
        ok = isinstance(c, int) and not isinstance(c, bool) and c >= 0 and isinstance(payload.get("op"), str)
        return c if ok else None
    return 0


def canonical(payload: dict[str, Any]) -> str:
    """Canonical JSON of a payload: sorted keys, no spaces (floats as Python's shortest repr)."""
    return json.dumps(payload, sort_keys=True, separators=(",", ":"), allow_nan=False)


def mac_input(line: bytes) -> bytes:
    """The bytes a record's MAC covers: the line with its trailing ``,"mac":"..."`` member removed."""
    return line[:-MAC_SUFFIX_LEN] + b"}"


def line_hash(line: bytes) -> str:
    """SHA-256 (hex) of one record line without its newline."""
    return hashlib.sha256(line).hexdigest()


class _Hmac:
    """HMAC-SHA256 with the key's inner and outer pad states precomputed (RFC 2104; same output as ``hmac``)."""

    def __init__(self, key: bytes) -> None:
        block = key if len(key) <= 64 else hashlib.sha256(key).digest()
        block = block.ljust(64, b"\0")
        self._inner = hashlib.sha256(bytes(b ^ 0x36 for b in block))
        self._outer = hashlib.sha256(bytes(b ^ 0x5C for b in block))

    def hexdigest(self, message: bytes) -> str:
        inner = self._inner.copy()
        inner.update(message)
        outer = self._outer.copy()
        outer.update(inner.digest())
        return outer.hexdigest()


class LedgerWriter:
    """Appends chained records to a new ledger file; the only holder of the key in the server.

    Args:
        path: The ledger file; must not exist yet.
        key: HMAC key [bytes], at least 16 bytes.
        task_id: Task the ledger belongs to.
        meta: Extra fields of the open record's payload (model digest, budget, ...).
    """

    def __init__(self, path: Path, key: bytes, task_id: str, meta: dict[str, Any] | None = None) -> None:
        if len(key) < 16:
            raise LedgerError(
                f"ledger key must have at least 16 bytes, got {len(key)}", code="ledger.weak_key"
            )
        self.path = Path(path)
        try:
            fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
        except FileExistsError:
            raise LedgerError(
                f"ledger {self.path} exists already; a session never appends to an old ledger",
                code="ledger.exists",
                path=str(self.path),
            ) from None
        self._file = os.fdopen(fd, "wb", buffering=1 << 16)
        self._mac = _Hmac(key)
        self._task_json = json.dumps(task_id)
        self.task_id = task_id
        self.seq = 0
        self.prev = GENESIS
        self.sealed = False
        open_payload = {
            "format": FORMAT,
            "attempt": "",
            "nonce": secrets.token_hex(16),
            "created": round(time.time(), 3),
            **(meta or {}),
        }
        self.ledger_id = self._append("open", canonical(open_payload))

    def _append(self, kind: str, payload_json: str) -> str:
        digest = hashlib.sha256(payload_json.encode()).hexdigest()
        body = (
            f'{{"seq":{self.seq},"kind":"{kind}","task_id":{self._task_json},"prev":"{self.prev}",'
            f'"digest":"{digest}","payload":{payload_json}'
        ).encode()
        mac = self._mac.hexdigest(body + b"}")
        line = body + b',"mac":"' + mac.encode() + b'"}'
        self._file.write(line + b"\n")
        self.prev = hashlib.sha256(line).hexdigest()
        self.seq += 1
        return self.prev

    def append(self, kind: str, payload: dict[str, Any]) -> str:
        """Append a ``reset`` or ``steps`` record (canonical payload); returns the new head hash."""
        if self.sealed:
            raise LedgerError(
                f"ledger {self.path} is sealed; no records after the seal", code="ledger.sealed"
            )
        if kind not in CHARGED:
            raise LedgerError(f"record kind '{kind}' cannot be appended. Kinds: {', '.join(CHARGED)}")
        return self._append(kind, canonical(payload))

    def append_steps(self, action_hexes: list[str], steps: int, sim_time: float, wall: float) -> str:
        """Fast path of ``append("steps", {"actions": ..., "steps": ..., "time": ..., "wall": ...})`` (same bytes).

        Args:
            action_hexes: Each action's float64 bytes in hex, in execution order (non-empty).
            steps: Charged steps used after the last of them.
            sim_time: Simulation time after the last of them [s].
            wall: Session wall clock when the last of them was charged [s].
        """
        if self.sealed:
            raise LedgerError(
                f"ledger {self.path} is sealed; no records after the seal", code="ledger.sealed"
            )
        if not action_hexes:
            raise LedgerError("a steps record needs at least one action", code="ledger.error")
        # Hex strings need no escaping, keys are sorted and json.dumps writes floats with
        # float.__repr__: the bytes are identical to canonical().
        actions = '","'.join(action_hexes)
        return self._append(
            "steps",
            f'{{"actions":["{actions}"],"steps":{steps:d},"time":{sim_time!r},"wall":{float(wall)!r}}}',
        )

    def seal(self, steps: int, extra: dict[str, Any] | None = None) -> str:
        """Write the seal (record count, step count, head, ledger id, then ``extra`` such as the wall
        time used), flush and close; returns the seal hash."""
        if self.sealed:
            raise LedgerError(f"ledger {self.path} is sealed already", code="ledger.sealed")
        reserved = {"head", "ledger", "records", "steps"} & set(extra or {})
        if reserved:
            raise ValueError(f"seal fields {sorted(reserved)} are reserved")
        payload = {
            **(extra or {}),
            "head": self.prev,
            "ledger": self.ledger_id,
            "records": self.seq,
            "steps": steps,
        }
        head = self._append("seal", canonical(payload))
        self.sealed = True
        self._file.flush()
        os.fsync(self._file.fileno())
        self._file.close()
        return head

    def flush(self) -> None:
        """Push buffered records to the file."""
        if not self._file.closed:
            self._file.flush()
