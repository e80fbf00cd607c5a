"""The development server of the ``06-pose-*`` tasks: a separate process that owns the scene.

The agent's ``pose_client.py`` talks to it over a Unix socket with the sandbox's typed, pickle-free
frames (``rle_design.ledger.server.encode``/``decode``), so meshes, the scene and the ledger key stay
in this process. Operations:

- ``frames`` ``{seed, n, raised}``: ``n`` (<= 64) independent labelled frames of a public seed (free);
- ``episode`` ``{seed, n}``: a push episode of ``n`` (<= 60) labelled frames (free);
- ``evaluate``: the workspace's current submission on the public design set (charged: one record in
  the sealed ledger; at most ``EVALUATIONS`` calls);
- ``info``: evaluations used and left; ``seal``: close the ledger and stop.

Labels are ``(x, y, theta)`` with the noise of ``devserver.LABEL_NOISE``; shapes are withheld.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import signal
from multiprocessing.connection import Connection, Listener
from pathlib import Path
from typing import Any

from rle_design.ledger.records import LedgerError, LedgerWriter
from rle_design.ledger.server import MAX_MESSAGE_BYTES, decode, encode
from rle_design.sandbox import codec

EVALUATIONS = 6
"""Design-set evaluation calls per development session (the card)."""
MAX_FRAMES = 64
"""Largest number of frames of one render request."""


class _Stop(Exception):
    pass


def _on_signal(signum: int, frame: Any) -> None:
    raise _Stop


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


def serve(
    task_id: str,
    workspace: str,
    socket_path: str,
    key: bytes | None,
    ledger_path: str | None,
    ready: Connection | None = None,
) -> None:
    """Serve one development session until sealed or signalled (runs in the server process)."""
    signal.signal(signal.SIGTERM, _on_signal)
    signal.signal(signal.SIGINT, _on_signal)
    writer = LedgerWriter(Path(ledger_path), key, task_id, {"evaluations": EVALUATIONS}) if key else None
    del key
    session = _Session(task_id, Path(workspace), writer)
    old = os.umask(0o077)
    try:
        listener = Listener(socket_path, family="AF_UNIX")
    finally:
        os.umask(old)
    if ready is not None:
        ready.send("ready")
        ready.close()
    try:
        while not session.sealed:
            with listener.accept() as conn:
                while not session.sealed:
                    try:
                        message = conn.recv_bytes(MAX_MESSAGE_BYTES)
                    except (EOFError, OSError):
                        break
                    try:
                        reply = encode(*session.handle(*decode(message)))
                    except LedgerError as exc:
                        reply = encode({"ok": False, "code": exc.code, "message": exc.message})
                    except codec.CodecError as exc:
                        reply = encode({"ok": False, "code": "ledger.bad_request", "message": str(exc)})
                    conn.send_bytes(reply)
    except _Stop:
        pass
    finally:
        session.seal()
        listener.close()


def start(task_id: str, workspace: Path, socket_path: Path, key: bytes | None, ledger_path: Path | None):
    """Start ``serve`` in a spawned process and wait until it listens; returns the process."""
    ctx = mp.get_context("spawn")
    parent, child = ctx.Pipe(duplex=False)
    proc = ctx.Process(
        target=serve,
        args=(
            task_id,
            str(workspace),
            str(socket_path),
            key,
            str(ledger_path) if ledger_path else None,
            child,
        ),
        name=f"rle-dev-{task_id}",
    )
    proc.start()
    child.close()
    if not parent.poll(180):
        proc.terminate()
        raise LedgerError("the development server did not start within 180 s", code="ledger.server")
    parent.recv()
    return proc
