"""Verification of a sealed ledger: integrity (MACs, chain) and completeness (seal, counts)."""

from __future__ import annotations

import hashlib
import hmac
import json
import re
from dataclasses import dataclass, field
from pathlib import Path

from rle_design.ledger.records import CHARGED, GENESIS, KINDS, canonical, cost, line_hash, mac_input

_MAC_TAIL = re.compile(rb',"mac":"([0-9a-f]{64})"\}$')
_FIELDS = ("seq", "kind", "task_id", "prev", "digest", "payload", "mac")

#: Verdict codes, one per way a ledger can fail.
VERDICT_CODES: dict[str, str] = {
    "ledger.valid": "sealed, complete and authentic",
    "ledger.missing": "the ledger file does not exist or cannot be read",
    "ledger.empty": "the ledger file holds no record",
    "ledger.malformed": "a line is not a ledger record",
    "ledger.truncated": "the file ends mid-record or records are missing",
    "ledger.forged_key": "no record carries a MAC made with the verifier's key",
    "ledger.unsealed": "the ledger has no seal record",
    "ledger.replayed_seal": "the seal appears twice or belongs to another ledger",
    "ledger.after_seal": "records follow the seal",
    "ledger.altered": "a record was changed after it was written",
    "ledger.wrong_task": "the ledger belongs to another task",
    "ledger.reordered": "records are out of order",
    "ledger.broken_chain": "a record does not chain to its predecessor",
}


@dataclass(frozen=True)
class LedgerVerdict:
    """Result of ``verify_ledger``.

    Attributes:
        valid: True only for a sealed, complete, authentic ledger of the expected task.
        code: ``"ledger.valid"`` or the first failure found (see ``VERDICT_CODES``).
        message: Human-readable reason naming the line.
        steps: Charged steps recorded by the seal (0 when not valid).
        head: SHA-256 of the seal line (empty when not valid).
        opened: Payload of the open record (nonce, model digest, budget, ``wall_time_s`` ...) of a
            valid ledger (empty otherwise).
        sealed: Payload of the seal record of a valid ledger (``elapsed_s`` when time-limited).
    """

    valid: bool
    code: str
    message: str
    steps: int = 0
    head: str = ""
    opened: dict = field(default_factory=dict)
    sealed: dict = field(default_factory=dict)


def _digest(payload: dict) -> str:
    try:
        return hashlib.sha256(canonical(payload).encode()).hexdigest()
    except (TypeError, ValueError):
        return ""


def _fail(code: str, message: str) -> LedgerVerdict:
    return LedgerVerdict(False, code, message)


def _parse(raw: bytes, lineno: int) -> dict | str:
    try:
        rec = json.loads(raw)
    except (ValueError, RecursionError):
        return f"line {lineno} is not JSON"
    if not isinstance(rec, dict) or tuple(rec) != _FIELDS:
        return f"line {lineno} does not have the fields {', '.join(_FIELDS)} in order"
    ok = (
        isinstance(rec["seq"], int)
        and not isinstance(rec["seq"], bool)
        and rec["kind"] in KINDS
        and isinstance(rec["task_id"], str)
        and isinstance(rec["payload"], dict)
        and all(isinstance(rec[k], str) and len(rec[k]) == 64 for k in ("prev", "digest", "mac"))
    )
    return rec if ok else f"line {lineno} has a field of the wrong type"


def verify_ledger(path: str | Path, key: bytes, task_id: str | None = None) -> LedgerVerdict:
    """Check a ledger file against ``key`` (and ``task_id`` when given).

    Args:
        path: The ledger (JSON lines).
        key: The HMAC key the server held [bytes].
        task_id: Expected task; None accepts the task named by the open record.

    Returns:
        A verdict; never raises on bad input.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        return _fail("ledger.missing", f"ledger {path.name} cannot be read: {exc.strerror or exc}")
    if not data:
        return _fail("ledger.empty", f"ledger {path.name} is empty")
    if not data.endswith(b"\n"):
        return _fail("ledger.truncated", f"ledger {path.name} ends mid-record (no final newline)")
    lines = data[:-1].split(b"\n")
    recs: list[dict] = []
    for i, raw in enumerate(lines, start=1):
        rec = _parse(raw, i)
        if isinstance(rec, str):
            return _fail("ledger.malformed", f"{path.name}: {rec}")
        recs.append(rec)
    macs_ok = [
        (m := _MAC_TAIL.search(raw)) is not None
        and hmac.compare_digest(hmac.digest(key, mac_input(raw), "sha256").hex(), m.group(1).decode())
        for raw in lines
    ]
    if not any(macs_ok):
        return _fail("ledger.forged_key", f"{path.name}: no record has a valid MAC under the verifier's key")
    seals = [i for i, r in enumerate(recs) if r["kind"] == "seal"]
    if not seals:
        return _fail("ledger.unsealed", f"{path.name}: no seal record (session not closed, or truncated)")
    if len(seals) > 1:
        return _fail("ledger.replayed_seal", f"{path.name}: seal appears {len(seals)} times (lines {seals[0] + 1}, "
                     f"{seals[1] + 1})")  # fmt: skip
    if seals[0] != len(recs) - 1:
        n_after = len(recs) - 1 - seals[0]
        return _fail(
            "ledger.after_seal", f"{path.name}: {n_after} record(s) after the seal on line {seals[0] + 1}"
        )
    for i, ok in enumerate(macs_ok):
        if not ok:
            return _fail("ledger.altered", f"{path.name}: line {i + 1} (seq {recs[i]['seq']}) fails its MAC")
    expected_task = task_id if task_id is not None else recs[0]["task_id"]
    for i, rec in enumerate(recs):
        if rec["task_id"] != expected_task:
            return _fail(
                "ledger.wrong_task",
                f"{path.name}: line {i + 1} belongs to task '{rec['task_id']}', expected '{expected_task}'",
            )
    seal = recs[-1]["payload"]
    if recs[0]["kind"] != "open" or seal.get("ledger") != line_hash(lines[0]):
        return _fail("ledger.replayed_seal", f"{path.name}: the seal belongs to another ledger")
    seqs = [r["seq"] for r in recs]
    if seqs != list(range(len(recs))):
        if sorted(seqs) == list(range(len(recs))):
            first = next(i for i, s in enumerate(seqs) if s != i)
            return _fail(
                "ledger.reordered", f"{path.name}: line {first + 1} holds seq {seqs[first]}, expected {first}"
            )
        first = next((i for i, s in enumerate(seqs) if s != i), len(seqs))
        return _fail(
            "ledger.truncated",
            f"{path.name}: records missing before line {first + 1} (seq {seqs[first]}, expected {first})",
        )
    prev = GENESIS
    for i, (raw, rec) in enumerate(zip(lines, recs)):
        if rec["prev"] != prev:
            return _fail("ledger.broken_chain", f"{path.name}: line {i + 1} does not chain to line {i}")
        if rec["digest"] != _digest(rec["payload"]):
            return _fail("ledger.altered", f"{path.name}: line {i + 1} payload does not match its digest")
        prev = line_hash(raw)
    steps = 0
    for i, rec in enumerate(recs):
        if rec["kind"] in CHARGED:
            n = cost(rec["kind"], rec["payload"])
            if n is None:
                return _fail(
                    "ledger.malformed",
                    f"{path.name}: line {i + 1} is a {rec['kind']} record without actions or a valid cost",
                )
            steps += n
            if rec["payload"].get("steps") != steps:
                return _fail(
                    "ledger.altered",
                    f"{path.name}: line {i + 1} counts {rec['payload'].get('steps')} steps, the records before it {steps}",
                )
    if (
        seal.get("records") != len(recs) - 1
        or seal.get("head") != recs[-1]["prev"]
        or seal.get("steps") != steps
    ):
        return _fail(
            "ledger.altered",
            f"{path.name}: seal counts {seal.get('records')} records / {seal.get('steps')} steps, "
            f"found {len(recs) - 1} / {steps}",
        )
    return LedgerVerdict(
        True,
        "ledger.valid",
        f"{path.name}: sealed, {steps} steps",
        steps,
        line_hash(lines[-1]),
        dict(recs[0]["payload"]),
        dict(seal),
    )
