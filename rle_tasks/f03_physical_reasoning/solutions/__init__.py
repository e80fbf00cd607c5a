"""Shipped solutions of the family's tabletop tasks (one ``SolutionSet`` per task module).

Artifacts are sealed ledgers recorded under the public development key by ``make_ledgers`` running the
agent programs of ``agents`` (which read privileged piece poses; see there):

- ``reference`` (``reference/<task>/ledger.jsonl``): cantilever: harmonic stack at 0.93 of its
  critical offsets; tower: the optimal order of ``tower_optimum`` without the wedge.
- ``baseline/overreach`` (cantilever): harmonic stack at 1.15 of its critical offsets: past its
  tipping point, the top blocks fall.
- ``baseline/knocked_over`` (tower): the reference tower, then the arm sweeps through it.
- ``baseline/unsealed`` (both): the reference ledger with its seal record cut off (score 0, reason
  ``ledger.unsealed``).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any


def unseal(directory: Path) -> None:
    """Cut the seal (the last record) off ``ledger.jsonl``."""
    path = directory / "ledger.jsonl"
    lines = path.read_bytes().splitlines(keepends=True)
    path.write_bytes(b"".join(lines[:-1]))


def record_session(
    env,
    secret,
    task_id: str,
    budget: int,
    ledger: Path,
    solve: Callable[..., Any],
    wall_time_s: float,
    **kwargs,
) -> Path:
    """Play ``solve(client, **kwargs)`` on a metered session of ``env`` served by a ledger server under
    ``secret``'s key, in ``secret``'s attempt, time-limited by ``wall_time_s`` [s] as the card's
    sessions are; seal it, and return the sealed ledger file ``ledger`` (replaced if present)."""
    import tempfile

    from rle_design.ledger import LedgerClient, LedgerServer
    from rle_tasks.core.devenv import ledger_key

    ledger = Path(ledger)
    ledger.parent.mkdir(parents=True, exist_ok=True)
    ledger.unlink(missing_ok=True)
    with tempfile.TemporaryDirectory(prefix="rle-f03-") as tmp:
        server = LedgerServer(
            env,
            key=ledger_key(secret, task_id),
            ledger_path=ledger,
            socket_path=Path(tmp) / "ledger.sock",
            task_id=task_id,
            budget=budget,
            wall_time_s=wall_time_s,
            attempt=secret.attempt,
        )
        server.start()
        try:
            with LedgerClient(server.socket_path) as client:
                solve(client, **kwargs)
                client.seal()
            server.wait(60)
        finally:
            server.stop()
    return ledger
