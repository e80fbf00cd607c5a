"""Ledger-format cases: a clean sealed session ledger tampered in one place (cut, reordered, altered,
replayed, re-keyed), each refused by ``rle_design.ledger.verify`` with its code. The ledger is one of
``03-tower``'s (any metered task's would do: the format and its MAC chain are the toolkit's)."""

from __future__ import annotations

import struct
from collections.abc import Callable
from pathlib import Path

from rle_design.ledger.records import LedgerWriter
from rle_design.ledger.verify import verify_ledger
from rle_tasks.audit.case import Case
from rle_tasks.core.report import ErrorEntry, VerifierReport
from rle_tasks.core.runtime.secrets import Secret

__all__ = ["LEDGER_TASK", "ledger_cases"]

LEDGER_TASK = "03-tower"


def _ledger_key(secret: Secret) -> bytes:
    from rle_tasks.core.runtime.devenv import ledger_key

    return ledger_key(secret, LEDGER_TASK)


def _ledger(
    tamper: Callable[[list[bytes]], list[bytes]], *, task: str = LEDGER_TASK, key: bytes | None = None
):
    """A clean 20-step sealed ledger written with the audit secret, then tampered."""

    def build(d: Path) -> Path:
        from rle_tasks.audit.case import AUDIT_SECRET

        path = d / "ledger.jsonl"
        w = LedgerWriter(path, key or _ledger_key(AUDIT_SECRET), task)
        w.append("reset", {"seed": 0, "steps": 1})
        for i in range(19):
            action = struct.pack("<2d", 0.1 * i, 0.0).hex()
            w.append_steps([action], steps=i + 2, sim_time=0.02 * (i + 1), wall=0.0)
        w.seal(20)
        lines = path.read_bytes().splitlines(keepends=True)
        path.write_bytes(b"".join(tamper(lines)))
        return d

    return build


def _run_ledger(artifact: Path, secret: Secret) -> VerifierReport:
    verdict = verify_ledger(artifact / "ledger.jsonl", _ledger_key(secret), LEDGER_TASK)
    errors = () if verdict.valid else (ErrorEntry(verdict.code, verdict.message, "ledger.jsonl"),)
    return VerifierReport(
        task_id=LEDGER_TASK, family="03", workflow="interactive_control", valid=verdict.valid, errors=errors
    )


def _alter(lines: list[bytes]) -> list[bytes]:
    """Change one hex digit of the action recorded on line 6 (the MAC no longer matches)."""
    i = lines[5].index(b'"actions":["') + len(b'"actions":["')
    digit = b"1" if lines[5][i : i + 1] != b"1" else b"2"
    lines[5] = lines[5][:i] + digit + lines[5][i + 1 :]
    return lines


def _ledger_case(name: str, expect: str, build) -> Case:
    return Case(f"ledger/{name}", LEDGER_TASK, expect, build, run=_run_ledger, wall_cap_s=5.0)


def ledger_cases() -> list[Case]:
    return [
        _ledger_case("missing", "ledger.missing", lambda d: d),
        _ledger_case("empty", "ledger.empty", _ledger(lambda ls: [])),
        _ledger_case("unsealed", "ledger.unsealed", _ledger(lambda ls: ls[:-1])),
        _ledger_case("truncated_mid_record", "ledger.truncated", _ledger(lambda ls: ls[:-1] + [ls[-1][:40]])),
        _ledger_case("truncated_middle", "ledger.truncated", _ledger(lambda ls: ls[:5] + ls[9:])),
        _ledger_case("reordered", "ledger.reordered", _ledger(lambda ls: ls[:3] + [ls[4], ls[3]] + ls[5:])),
        _ledger_case("altered_field", "ledger.altered", _ledger(_alter)),
        _ledger_case("replayed_seal", "ledger.replayed_seal", _ledger(lambda ls: ls + [ls[-1]])),
        _ledger_case("after_seal", "ledger.after_seal", _ledger(lambda ls: ls + [ls[3]])),
        _ledger_case(
            "malformed_line", "ledger.malformed", _ledger(lambda ls: ls[:2] + [b"not json\n"] + ls[2:])
        ),
        _ledger_case("forged_key", "ledger.forged_key", _ledger(lambda ls: ls, key=b"k" * 32)),
        _ledger_case("other_task", "ledger.wrong_task", _ledger(lambda ls: ls, task="03-cantilever")),
        _ledger_case(
            "other_secret",
            "ledger.forged_key",
            lambda d: _ledger(lambda ls: ls, key=_ledger_key(Secret(b"another-secret", public=False)))(d),
        ),
    ]
