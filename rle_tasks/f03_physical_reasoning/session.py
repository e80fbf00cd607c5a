"""The family's ledger gate: a sealed, authentic ledger of the task, replayed to its final state.

A submission is the directory holding ``ledger.jsonl``, the sealed ledger the metered server wrote
for the agent's session. ``final_poses`` checks it with ``verify_ledger`` under the task's ledger key
(derived from the verifier secret, ``rle_tasks.core.devenv.ledger_key``); a missing, unsealed,
truncated or altered ledger fails with the verdict's code and message. A valid ledger is replayed on
the instance's environment (``rle_design.control.replay``): the scene is rebuilt from the secret, the
recorded resets and actions re-executed, and the free pieces' final poses read off. The poses are
thus exactly those the session ended with; no pose is taken from the submission itself.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rle_design.control import ReplayError, TabletopEnv, replay
from rle_design.ledger import verify_ledger
from rle_tasks.core.devenv import ledger_key
from rle_tasks.core.secrets import Secret

from .scene import Piece, piece_poses

__all__ = ["LEDGER_FILE", "LedgerOutcome", "final_poses"]

LEDGER_FILE = "ledger.jsonl"


@dataclass(frozen=True)
class LedgerOutcome:
    """Result of the ledger gate.

    Attributes:
        ok: The ledger is valid and replayed.
        code: ``"ledger.valid"`` or the failure code.
        message: Reason, naming the line or record.
        poses: Final pose of each piece (x, y, z, qw, qx, qy, qz) [m] (empty unless ``ok``).
        steps: Charged steps the seal records.
    """

    ok: bool
    code: str
    message: str
    poses: dict[str, np.ndarray]
    steps: int = 0


def final_poses(
    root: Path, secret: Secret, task_id: str, env: TabletopEnv, pieces: tuple[Piece, ...]
) -> LedgerOutcome:
    """Verify ``root/ledger.jsonl`` and replay it on ``env``; never raises on a bad ledger."""
    path = Path(root) / LEDGER_FILE
    if path.is_symlink() or (path.exists() and not path.is_file()):
        return LedgerOutcome(False, "ledger.missing", f"{LEDGER_FILE} is not a regular file", {})
    verdict = verify_ledger(path, ledger_key(secret, task_id), task_id)
    if not verdict.valid:
        return LedgerOutcome(False, verdict.code, verdict.message, {})
    try:
        model, data, _ = replay(env, path)
    except ReplayError as exc:
        return LedgerOutcome(False, exc.code, exc.message, {})
    return LedgerOutcome(True, verdict.code, verdict.message, piece_poses(model, data, pieces), verdict.steps)
