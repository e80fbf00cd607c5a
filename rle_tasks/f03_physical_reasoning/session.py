"""The family's ledger gate: a sealed, authentic ledger of the task, replayed to its final state.

A submission is the directory holding ``ledger.jsonl``, the sealed ledger the metered server wrote
for the agent's session. ``replay_ledger`` checks it with ``verify_ledger`` under the task's ledger
key (derived from the verifier secret, ``rle_tasks.core.devenv.ledger_key``); a missing, unsealed,
truncated or altered ledger fails with the verdict's code and message. With ``wall_time_s`` the
session must also have been limited to that wall time by its server (``ledger.no_time_limit``
otherwise). A valid ledger is replayed on the instance's environment (``rle_design.control.replay``):
the scene is rebuilt from the secret and the recorded resets and actions re-executed, so the final
state is exactly the one the session ended with; nothing is taken from the submission itself.
``final_poses`` reads the free pieces' poses off that state.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import mujoco
import numpy as np

from rle_design.control import ReplayError, TabletopEnv, replay
from rle_design.ledger import verify_ledger
from rle_tasks.core.devenv import ledger_key
from rle_tasks.core.secrets import Secret

from .scene import Piece, piece_poses

__all__ = ["LEDGER_FILE", "LedgerOutcome", "final_poses", "replay_ledger"]

LEDGER_FILE = "ledger.jsonl"


@dataclass(frozen=True)
class LedgerOutcome:
    """Result of the ledger gate.

    Attributes:
        ok: The ledger is valid and replayed.
        code: ``"ledger.valid"`` or the failure code.
        message: Reason, naming the line or record.
        poses: Final pose of each piece (x, y, z, qw, qx, qy, qz) [m] (``final_poses`` only).
        steps: Charged steps the seal records.
        model: The replayed model (None unless ``ok``).
        data: The replayed final state (None unless ``ok``).
        actions: Executed actions replayed.
        elapsed_s: Wall time the seal records for a time-limited session [s] (None otherwise).
    """

    ok: bool
    code: str
    message: str
    poses: dict[str, np.ndarray]
    steps: int = 0
    model: mujoco.MjModel | None = None
    data: mujoco.MjData | None = None
    actions: int = 0
    elapsed_s: float | None = None


def replay_ledger(
    root: Path, secret: Secret, task_id: str, env: TabletopEnv, wall_time_s: float | None = None
) -> LedgerOutcome:
    """Verify ``root/ledger.jsonl`` (time-limited to ``wall_time_s`` [s] when given) and replay it on
    ``env``; never raises on a bad ledger."""
    path = Path(root) / LEDGER_FILE
    if path.is_symlink() or (path.exists() and not path.is_file()):
        return LedgerOutcome(False, "ledger.missing", f"{LEDGER_FILE} is not a regular file", {})
    verdict = verify_ledger(path, ledger_key(secret, task_id), task_id)
    if not verdict.valid:
        return LedgerOutcome(False, verdict.code, verdict.message, {})
    limit = verdict.opened.get("wall_time_s")
    if wall_time_s is not None and not (isinstance(limit, (int, float)) and 0 < limit <= wall_time_s):
        return LedgerOutcome(
            False,
            "ledger.no_time_limit",
            f"{LEDGER_FILE}: the session was limited to {limit!r} s of wall time, the task allows "
            f"{wall_time_s:.0f} s; record it in the task's metered environment (rle dev)",
            {},
        )
    try:
        model, data, n_actions = replay(env, path)
    except ReplayError as exc:
        return LedgerOutcome(False, exc.code, exc.message, {})
    elapsed = verdict.sealed.get("elapsed_s")
    return LedgerOutcome(
        True,
        verdict.code,
        verdict.message,
        {},
        verdict.steps,
        model,
        data,
        n_actions,
        float(elapsed) if isinstance(elapsed, (int, float)) else None,
    )


def final_poses(
    root: Path, secret: Secret, task_id: str, env: TabletopEnv, pieces: tuple[Piece, ...]
) -> LedgerOutcome:
    """``replay_ledger`` and the final pose of each of ``pieces``; never raises on a bad ledger."""
    gate = replay_ledger(root, secret, task_id, env)
    if not gate.ok:
        return gate
    return replace(gate, poses=piece_poses(gate.model, gate.data, pieces))
