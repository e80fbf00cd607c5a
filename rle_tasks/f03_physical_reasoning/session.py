"""The family's ledger gate: a sealed ledger of the task, checked against the card, replayed to its final state.

A submission is the directory holding ``ledger.jsonl``, the sealed ledger the metered server wrote
for the agent's session. ``open_ledger`` passes it through the shared gate
(``rle_design.ledger.check_ledger``) under the task's ledger key (derived from the verifier secret,
``rle_tasks.core.runtime.devenv.ledger_key``) with the card's ``Limits``: a missing, unsealed, truncated or
altered ledger, one of another attempt, one served with other limits (budget, wall time) or one that
breaks them on its own records fails with the gate's code and message. The instance is then drawn
from the secret bound to the ledger's attempt (``OpenedLedger.secret``), and ``replay_ledger``
replays the ledger on its environment (``rle_design.control.replay``): the scene is rebuilt and the
recorded resets and actions re-executed, so the final state is exactly the one the session ended
with; nothing is taken from the submission itself. ``final_poses`` reads the free pieces' poses and
velocities off that state.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import mujoco
import numpy as np

from rle_design.control import ReplayError, TabletopEnv, replay
from rle_design.ledger import GateResult, Limits, check_ledger
from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.runtime.devenv import ledger_key
from rle_tasks.core.runtime.secrets import Secret
from rle_tasks.core.scoring import Outcome, Rubric

from .constants import STEP_BUDGET, WALL_TIME_S
from .scene import Piece, make_env, piece_poses, piece_velocities

__all__ = [
    "LEDGER_FILE",
    "LedgerOutcome",
    "OpenedLedger",
    "SettledPieces",
    "final_poses",
    "invalid_report",
    "open_ledger",
    "replay_ledger",
    "settled_pieces",
    "tabletop_limits",
]

LEDGER_FILE = "ledger.jsonl"


def tabletop_limits(budget: int, wall_time_s: float) -> Limits:
    """The card's limits of a tabletop session: ``budget`` charged steps in ``wall_time_s`` [s]."""
    return Limits(budget=budget, wall_time_s=wall_time_s)


@dataclass(frozen=True)
class OpenedLedger:
    """A ledger through the gate (``ok``) or the reason it was refused.

    Attributes:
        ok: Authentic, of the attempt, within the card's limits.
        code: ``"ledger.valid"`` or the failure code.
        message: Reason, naming the line or record.
        path: The ledger file.
        gate: The gate's result (counts, attempt).
        secret: The verifier secret bound to the ledger's attempt (draw the instance from it).
    """

    ok: bool
    code: str
    message: str
    path: Path
    gate: GateResult
    secret: Secret

    @property
    def attempt(self) -> dict:
        return {"id": self.gate.attempt, "bound": self.gate.attempt_bound}


@dataclass(frozen=True)
class LedgerOutcome:
    """Result of the ledger gate and the replay.

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
        velocities: Final free-joint velocity of each piece (vx, vy, vz, wx, wy, wz) [m/s, rad/s]
            (``final_poses`` only).
        attempt: The ledger's attempt and whether the verification named it.
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
    velocities: dict[str, np.ndarray] = field(default_factory=dict)
    attempt: dict = field(default_factory=dict)


def open_ledger(
    root: Path, secret: Secret, task_id: str, limits: Limits, attempt: str | None = None
) -> OpenedLedger:
    """``root/ledger.jsonl`` through the shared gate; never raises on a bad ledger."""
    path = Path(root) / LEDGER_FILE
    gate = check_ledger(path, ledger_key(secret, task_id), task_id, limits, attempt)
    message = gate.message
    if gate.code == "ledger.wrong_limits":
        message += "; record it in the task's metered environment (rle dev)"
    return OpenedLedger(gate.ok, gate.code, message, path, gate, secret.for_attempt(gate.attempt))


def invalid_report(rubric: Rubric, code: str, message: str, findings: Findings) -> VerifierReport:
    """The report of a session that did not pass the gate or the replay: ``code`` as an error on the
    ledger, every checkpoint's variants 0, invalid."""
    findings.add_error(code, message, LEDGER_FILE)
    outcomes = {
        c.id: Outcome(dict.fromkeys(rubric.variants, 0.0), f"no valid session: {message}")
        for c in rubric.checkpoints
    }
    return rubric.report(outcomes, valid=False, errors=findings.errors, native_metrics={"ledger": code})


def refused(opened: OpenedLedger) -> LedgerOutcome:
    """The outcome of a ledger the gate refused."""
    return LedgerOutcome(False, opened.code, opened.message, {}, attempt=opened.attempt)


def replay_ledger(opened: OpenedLedger, env: TabletopEnv) -> LedgerOutcome:
    """Replay a ledger that passed ``open_ledger`` on ``env``; never raises on a bad ledger."""
    if not opened.ok:
        return refused(opened)
    try:
        model, data, n_actions = replay(env, opened.path)
    except ReplayError as exc:
        return LedgerOutcome(False, exc.code, exc.message, {}, attempt=opened.attempt)
    elapsed = opened.gate.sealed.get("elapsed_s")
    return LedgerOutcome(
        True,
        opened.code,
        opened.message,
        {},
        opened.gate.steps,
        model,
        data,
        n_actions,
        float(elapsed) if isinstance(elapsed, (int, float)) else None,
        attempt=opened.attempt,
    )


def final_poses(opened: OpenedLedger, env: TabletopEnv, pieces: tuple[Piece, ...]) -> LedgerOutcome:
    """``replay_ledger`` and the final pose and velocity of each of ``pieces``."""
    gate = replay_ledger(opened, env)
    if not gate.ok:
        return gate
    return replace(
        gate,
        poses=piece_poses(gate.model, gate.data, pieces),
        velocities=piece_velocities(gate.model, gate.data, pieces),
    )


PRIVILEGED_MESSAGE = (
    "the session served privileged observations (piece poses and sizes; the cube's plan) for an operator's oracle trial "
    "(RLE_ORACLE_PRIVILEGED=1): its score is the reference program's, not an agent's; `rle index` refuses "
    "this report and a Harbor reward is 0 unless the verifier is also told it verifies the oracle"
)


def note_privileged(opened: OpenedLedger, findings) -> bool:
    """Add ``ledger.privileged`` to ``findings`` when the session was an oracle's; returns whether."""
    if opened.gate.privileged:
        findings.add_error("ledger.privileged", PRIVILEGED_MESSAGE, LEDGER_FILE)
    return opened.gate.privileged


@dataclass(frozen=True)
class SettledPieces:
    """A free-pieces session past the gate: the secret's instance, the replay with the pieces' final
    poses and velocities, and whether an oracle's privileged session was served."""

    instance: object
    gate: LedgerOutcome
    privileged: bool


def settled_pieces(
    root: Path, ctx, task_id: str, instance, rubric: Rubric, checkpoint: str, findings: Findings
) -> SettledPieces | VerifierReport:
    """The protocol of a task of free pieces on the shared table (tower, cantilever): the ledger gate
    with the card's limits, the instance of the ledger's attempt (``instance(secret)``, its ``pieces``),
    the replay and the pieces' final state; an invalid report scoring ``checkpoint`` 0 when the ledger
    fails."""
    opened = open_ledger(root, ctx.secret, task_id, tabletop_limits(STEP_BUDGET, WALL_TIME_S), ctx.attempt)
    inst = instance(opened.secret)
    gate = final_poses(opened, make_env(inst.pieces, images=False), inst.pieces)
    if not gate.ok:
        findings.add_error(gate.code, gate.message, LEDGER_FILE)
        outcome = Outcome({"scene": 0.0}, f"no score: {gate.message}")
        return rubric.report({checkpoint: outcome}, valid=False, errors=findings.errors)
    return SettledPieces(inst, gate, note_privileged(opened, findings))
