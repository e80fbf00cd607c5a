"""Verifiers of the family's tasks, by task id (each task module holds its own ``verify``).

Every tabletop verifier follows the same protocol: the ledger gate (``session.final_poses``: a
missing, unsealed, altered or non-replaying ledger scores 0 with its reason), the robot-free settle
of the final scene (``scene.settle``, ``SETTLE_S``), then the task's measurement.
"""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.report import VerifierReport
from rle_tasks.core.task import VerifyContext


def verify_cantilever(root: Path, ctx: VerifyContext) -> VerifierReport:
    from .cantilever import verify

    return verify(root, ctx)


def verify_tower(root: Path, ctx: VerifyContext) -> VerifierReport:
    from .tower import verify

    return verify(root, ctx)
