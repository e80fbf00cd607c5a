"""One adversarial artifact of the audit battery (``Case``), and the secret and mark every case shares."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from rle_tasks.core.report import VerifierReport
from rle_tasks.core.runtime.secrets import Secret

__all__ = ["AUDIT_SECRET", "EXFIL_MARK", "Case"]

AUDIT_SECRET = Secret(b"rle-audit-secret-7f3a9c1e5b2d", public=False)
EXFIL_MARK = "rle-exfil-payload"
"""Text a case's submitted code tries to smuggle into the report: it must never appear there."""


@dataclass(frozen=True)
class Case:
    """One adversarial artifact.

    Attributes:
        name: ``category/short_name``.
        task_id: Task whose verifier receives the artifact, or ``"ledger"`` for ledger-only cases.
        expect: Error code that must appear in the report's errors (None: the case bounds only the
            score, for behaviour the rubric scores down rather than names).
        build: Writes the artifact into the given empty directory and returns the directory to verify.
        max_score: Highest score allowed (0, or the documented cap).
        wall_cap_s: The case fails if verification takes longer [s].
        run: Custom runner returning a report (ledger cases); default runs the task's verifier.
        attempt: The attempt the verifier is told it verifies (``VerifyContext.attempt``).
    """

    name: str
    task_id: str
    expect: str | None
    build: Callable[[Path], Path]
    max_score: float = 0.0
    wall_cap_s: float = 60.0
    run: Callable[[Path, Secret], VerifierReport] | None = field(default=None, compare=False)
    attempt: str | None = None
