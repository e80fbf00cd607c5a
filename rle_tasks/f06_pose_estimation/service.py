"""The development session of the ``06-pose-*`` tasks, served by ``rle_tasks.core.runtime.devservice``.

The agent's ``pose_client.py`` talks to its process over a Unix socket, so meshes, the scene and the
ledger key stay there. Operations:

- ``frames`` ``{seed, n, raised}``: ``n`` (<= 64) independent labelled frames of a public seed (free);
- ``episode`` ``{seed, n}``: a push episode of ``n`` (<= 60) labelled frames (free);
- ``evaluate``: the workspace's current submission (every file of the workspace root, as the
  verifier reads a submission directory) on the public design set (charged: at most ``EVALUATIONS``
  per attempt, over every server process of the attempt);
- ``info``: evaluations used and left; ``seal``: close the ledger and stop.

Every request is a record of the sealed ledger (``rle_design.ledger.ServedLedger``): free requests
with their arguments, evaluations with the submission's sha256, the design-set score and the frame
rate (as the score counts it, and measured). Labels are ``(x, y, theta)`` with the noise of
``devserver.LABEL_NOISE``; shapes are withheld.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from rle_design.ledger.records import LedgerError
from rle_design.ledger.served import ServedLedger

EVALUATIONS = 6
"""Design-set evaluation calls per attempt (the card)."""
MAX_FRAMES = 64
"""Largest number of frames of one render request."""


class _Session:
    def __init__(self, task_id: str, workspace: Path, ledger: ServedLedger | None) -> None:
        from .contract import variant

        self.task_id = task_id
        self.variant = variant(task_id)
        self.workspace = workspace
        self.ledger = ledger
        self.used = 0
        self._sealed = False

    @property
    def sealed(self) -> bool:
        return self._sealed

    def _left(self) -> int:
        return self.ledger.left if self.ledger is not None else EVALUATIONS - self.used

    def handle(self, meta: dict[str, Any], value: Any) -> tuple[dict[str, Any], Any]:
        from rle_tasks.core.report import artifact_sha256

        from .devserver import design_evaluation, labelled_episode, labelled_frames

        op = meta.get("op")
        args = value if isinstance(value, dict) else {}
        depth = self.variant.depth
        if op in ("frames", "episode"):
            try:
                seed, n = int(args.get("seed", 0)), int(args.get("n", 10))
            except (TypeError, ValueError):
                raise LedgerError("seed and n must be integers", code="ledger.bad_request") from None
            limit = MAX_FRAMES if op == "frames" else 60
            if not 1 <= n <= limit:
                raise LedgerError(f"n must be in 1..{limit}, got {n}", code="ledger.bad_request")
            raised = bool(args.get("raised", False))
            if op == "frames":
                pairs = labelled_frames(seed, n, raised=raised, depth=depth)
                recorded = {"seed": seed, "n": n, "raised": raised}
            else:
                pairs = labelled_episode(seed, n, depth=depth)
                recorded = {"seed": seed, "n": n}
            if self.ledger is not None:
                self.ledger.record(op, recorded, 0, frames=len(pairs))
            return {"ok": True}, [{"obs": o, "label": lab} for o, lab in pairs]
        if op == "evaluate":
            if self.ledger is not None:
                self.ledger.check(1)
            elif self.used >= EVALUATIONS:
                raise LedgerError(
                    f"the {EVALUATIONS} design-set evaluations are used up", code="ledger.budget_exhausted"
                )
            digest = artifact_sha256(self.workspace)
            report = design_evaluation(self.task_id, self.workspace)
            self.used += 1
            if self.ledger is not None:
                self.ledger.record(
                    "evaluate",
                    {"directory": "."},
                    1,
                    submission_sha256=digest,
                    score=float(report["score"]),
                    fps=report.get("fps"),
                    fps_measured=report.get("fps_measured"),
                    gate=(report.get("gate") or {}).get("code"),
                )
            report = {**report, "submission_sha256": digest, "evaluations_left": self._left()}
            return {"ok": True, "used": self.used}, report
        if op == "info":
            if self.ledger is not None:
                return {"ok": True}, self.ledger.info()
            return {"ok": True}, {"evaluations_used": self.used, "evaluations_left": EVALUATIONS - self.used}
        if op == "seal":
            self.seal()
            return {"ok": True}, {"evaluations_used": self.used}
        raise LedgerError(
            f"unknown operation {op!r}. Operations: frames, episode, evaluate, info, seal",
            code="ledger.bad_request",
        )

    def seal(self) -> None:
        if not self._sealed and self.ledger is not None:
            self.ledger.seal()
        self._sealed = True


def open_session(
    *, key: bytes | None, ledger_path: Path | None, task_id: str, workspace: str, attempt: str = ""
) -> _Session:
    """The session of one development server (``rle_tasks.core.runtime.devservice`` factory)."""
    ledger = None
    if key is not None and ledger_path is not None:
        ledger = ServedLedger(
            ledger_path, key, task_id, budget=EVALUATIONS, unit="evaluations", attempt=attempt
        )
    return _Session(task_id, Path(workspace), ledger)
