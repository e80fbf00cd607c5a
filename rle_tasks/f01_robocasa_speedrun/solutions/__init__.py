"""Shipped solutions of family 01: sealed session ledgers recorded by the agent programs of ``agents``.

A submission is a session's sealed ledger (fresh nonce and opening time), so the programs are shipped
and ``make_ledgers`` records them under the public development key; the ledgers are committed gzipped
(``ledgers/<task id>/<name>/ledger.jsonl.gz``) and materialised by ``gunzip``.

| solution | tasks | expected score | why |
|---|---|---|---|
| ``reference`` | where a program exists for the level (see the README) | >= 0.8 x 4/5 | one pretrain episode of development, then the program on each of the five target kitchens |
| ``baseline/idle`` | all | 0 | enters the evaluation phase and never acts: five trials of zero actions |
| ``baseline/tampered`` | with a reference | 0 (``ledger.altered``) | the reference ledger with one recorded action changed after sealing |
| ``baseline/budget_exhausted`` | ``01-open-fridge-l1`` | 0 | develops until the server refuses the 50,001st step and never evaluates (d = 50,000) |
"""

from __future__ import annotations

import gzip
from pathlib import Path

from rle_tasks.core.solutions import Solution, SolutionSet

__all__ = ["LEDGER", "SOLUTIONS", "gunzip", "tamper"]

LEDGER = "ledger.jsonl"
PACKAGE = "rle_tasks.f01_robocasa_speedrun"


def gunzip(directory: Path) -> None:
    """Replace ``ledger.jsonl.gz`` by ``ledger.jsonl``."""
    gz = directory / (LEDGER + ".gz")
    (directory / LEDGER).write_bytes(gzip.decompress(gz.read_bytes()))
    gz.unlink()


def tamper(directory: Path) -> None:
    """Flip one hex digit of the last recorded action (the record's MAC no longer matches)."""
    path = directory / LEDGER
    lines = path.read_bytes().splitlines(keepends=True)
    k = max(i for i, line in enumerate(lines) if b'"kind":"steps"' in line)
    line = lines[k]
    at = line.rindex(b'"]') - 1
    digit = b"1" if line[at : at + 1] != b"1" else b"2"
    lines[k] = line[:at] + digit + line[at + 1 :]
    path.write_bytes(b"".join(lines))


def _ledger(task_id: str, name: str) -> tuple[tuple[str, str], ...]:
    return ((".", f"solutions/ledgers/{task_id}/{name.split('/')[-1]}"),)


def _set(task_id: str, pins: dict[str, tuple[str, float]]) -> SolutionSet:
    sols = []
    for name, (sha, score) in pins.items():
        if name == "baseline/tampered":
            sols.append(Solution(name, sha, score, base="reference", transforms=(tamper,)))
        else:
            sols.append(Solution(name, sha, score, files=_ledger(task_id, name), transforms=(gunzip,)))
    return SolutionSet(package=PACKAGE, solutions=tuple(sols))


PINS: dict[str, dict[str, tuple[str, float]]] = {}
"""Task id -> solution name -> (pinned checksum, golden score under the public key)."""

SOLUTIONS: dict[str, SolutionSet] = {task_id: _set(task_id, pins) for task_id, pins in PINS.items()}
"""Solution sets by task id (``rle_tasks.core.solutions.declaration``)."""
