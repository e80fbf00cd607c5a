"""The development session of the ``06-pose-*`` tasks, served by ``rle_tasks.core.devservice``.

The agent's ``pose_client.py`` talks to its process over a Unix socket, so meshes, the scene and the
ledger key stay there. Operations:

- ``frames`` ``{seed, n, raised}``: ``n`` (<= 64) independent labelled frames of a public seed (free);
- ``episode`` ``{seed, n}``: a push episode of ``n`` (<= 60) labelled frames (free);
- ``evaluate``: the workspace's current submission on the public design set (charged: one record in
  the sealed ledger; at most ``EVALUATIONS`` calls);
- ``info``: evaluations used and left; ``seal``: close the ledger and stop.

Labels are ``(x, y, theta)`` with the noise of ``devserver.LABEL_NOISE``; shapes are withheld.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from rle_design.ledger.records import LedgerError, LedgerWriter

EVALUATIONS = 6
"""Design-set evaluation calls per development session (the card)."""
MAX_FRAMES = 64
"""Largest number of frames of one render request."""


class _Session:
    def __init__(self, task_id: str, workspace: Path, writer: LedgerWriter | None) -> None:
        from .contract import variant

        self.task_id = task_id
        self.variant = variant(task_id)
        self.workspace = workspace
        self.writer = writer
        self.used = 0
        self.sealed = False

    def handle(self, meta: dict[str, Any], value: Any) -> tuple[dict[str, Any], Any]:
        from .devserver import design_evaluation, labelled_episode, labelled_frames

        op = meta.get("op")
        args = value if isinstance(value, dict) else {}
        depth = self.variant.depth
        if op in ("frames", "episode"):
            seed, n = int(args.get("seed", 0)), int(args.get("n", 10))
            if not 1 <= n <= (MAX_FRAMES if op == "frames" else 60):
                raise LedgerError(f"n must be in 1..{MAX_FRAMES if op == 'frames' else 60}, got {n}")
            if op == "frames":
                pairs = labelled_frames(seed, n, raised=bool(args.get("raised", False)), depth=depth)
            else:
                pairs = labelled_episode(seed, n, depth=depth)
            return {"ok": True}, [{"obs": o, "label": lab} for o, lab in pairs]
        if op == "evaluate":
            if self.used >= EVALUATIONS:
                raise LedgerError(
                    f"the {EVALUATIONS} design-set evaluations of this session are used up",
                    code="ledger.budget",
                )
            self.used += 1
            if self.writer is not None:
                self.writer.append("reset", {"steps": self.used, "time": 0.0})
                self.writer.flush()
            return {"ok": True, "used": self.used}, design_evaluation(self.task_id, self.workspace)
        if op == "info":
            return {"ok": True}, {"evaluations_used": self.used, "evaluations_left": EVALUATIONS - self.used}
        if op == "seal":
            self.seal()
            return {"ok": True}, {"evaluations_used": self.used}
        raise LedgerError(
            f"unknown operation {op!r}. Operations: frames, episode, evaluate, info, seal",
            code="ledger.bad_request",
        )

    def seal(self) -> None:
        if not self.sealed and self.writer is not None:
            self.writer.seal(self.used)
        self.sealed = True


def open_session(*, key: bytes | None, ledger_path: Path | None, task_id: str, workspace: str) -> _Session:
    """The session of one development server (``rle_tasks.core.devservice`` factory)."""
    writer = LedgerWriter(ledger_path, key, task_id, {"evaluations": EVALUATIONS}) if key else None
    return _Session(task_id, Path(workspace), writer)
