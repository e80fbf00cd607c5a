"""Record a metered session from a program: a ledger server on a temporary socket, the program as its
client, the seal. Solution generators (shipped ledgers) and tests use it; an agent's session is served
by ``rle dev`` instead (the server runs until the agent seals or its time runs out).
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from rle_design.ledger.client import LedgerClient
from rle_design.ledger.server import LedgerServer

__all__ = ["record_session"]


def record_session(
    env: Any,
    play: Callable[[LedgerClient], Any],
    ledger: Path,
    *,
    key: bytes,
    task_id: str,
    budget: int | None,
    wall_time_s: float | None = None,
    attempt: str = "",
    meta: dict | None = None,
    seal_timeout_s: float = 60.0,
) -> Path:
    """Serve ``env`` under ``key`` (``budget`` charged steps, ``wall_time_s`` [s], ``attempt``), run
    ``play(client)``, seal, and return the sealed ledger file ``ledger``.

    The session is recorded beside ``ledger`` and replaces it only once sealed, so a failed recording
    (``play`` raising, the server not starting) leaves a ledger already there as it was. The server
    stops even when ``play`` raises; the exception propagates.
    """
    ledger = Path(ledger)
    ledger.parent.mkdir(parents=True, exist_ok=True)
    with (
        tempfile.TemporaryDirectory(prefix="rle-record-", dir=ledger.parent) as part,
        tempfile.TemporaryDirectory(prefix="rle-record-") as tmp,  # a short socket path
    ):
        recording = Path(part) / ledger.name
        server = LedgerServer(
            env,
            key=key,
            ledger_path=recording,
            socket_path=Path(tmp) / "ledger.sock",
            task_id=task_id,
            budget=budget,
            wall_time_s=wall_time_s,
            attempt=attempt,
            meta=meta,
        )
        server.start()
        try:
            with LedgerClient(server.socket_path) as client:
                play(client)
                client.seal()
            server.wait(seal_timeout_s)
        finally:
            server.stop()
        os.replace(recording, ledger)
    return ledger
