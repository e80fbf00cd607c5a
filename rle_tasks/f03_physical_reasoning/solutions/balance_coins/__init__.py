"""Shipped agent programs of ``03-balance-coins`` and a runner that records their sealed ledgers.

A submission of this task is a session's sealed ledger, which carries a fresh nonce and the time of
its opening, so it cannot be committed with a pinned checksum: the programs are shipped instead and
``record`` plays one on a metered session of the secret's instance (in-process ``MeteredSession``,
the same environment, key and ledger format the ledger server uses) and writes the submission.

| program | expected score | why |
|---|---|---|
| ``reference`` | 1.0 | two weighings, heavy cube alone on the mat |
| ``five_weighings`` | 0.4 | right cube after five weighings: 2/5 |
| ``wrong_cube`` | 0.0 | a light cube on the mat |
"""

from __future__ import annotations

import importlib
from pathlib import Path

from rle_tasks.core.solutions import Solution, SolutionSet

PROGRAMS = {"reference": 1.0, "five_weighings": 0.4, "wrong_cube": 0.0}
"""Program -> expected score (any instance)."""
SHIPPED = ("reference", "five_weighings")
"""Programs whose public-key ledgers are committed (``ledgers/<name>/ledger.jsonl``, ``__main__`` records them)."""


def record(program: str, secret, dest: Path, **kwargs) -> Path:
    """Play ``program`` on the instance of ``secret``; write and return ``dest`` holding ``ledger.jsonl``."""
    import tempfile

    from rle_design.ledger import LedgerClient, LedgerServer
    from rle_tasks.core.devenv import ledger_key

    from ...balance import BUDGET_STEPS
    from ...balance_env import TASK_ID, make_env
    from ...balance_verifier import LEDGER_FILE, instance

    if program not in PROGRAMS:
        raise ValueError(f"unknown program {program!r}. Programs: {', '.join(PROGRAMS)}")
    solve = importlib.import_module(f"{__name__}.{program}").solve
    dest = Path(dest)
    dest.mkdir(parents=True, exist_ok=True)
    (dest / LEDGER_FILE).unlink(missing_ok=True)
    with tempfile.TemporaryDirectory(prefix="rle-f03-") as tmp:
        server = LedgerServer(
            make_env(instance(secret), image_size=None),
            key=ledger_key(secret, TASK_ID),
            ledger_path=dest / LEDGER_FILE,
            socket_path=Path(tmp) / "ledger.sock",
            task_id=TASK_ID,
            budget=BUDGET_STEPS,
        )
        server.start()
        try:
            with LedgerClient(server.socket_path) as client:
                solve(client, **kwargs)
                client.seal()
            server.wait(60)
        finally:
            server.stop()
    return dest


def _unseal(directory: Path) -> None:
    """Cut the seal (the last record) off ``ledger.jsonl``."""
    path = directory / "ledger.jsonl"
    lines = path.read_bytes().splitlines(keepends=True)
    path.write_bytes(b"".join(lines[:-1]))


SOLUTIONS = SolutionSet(
    package="rle_tasks.f03_physical_reasoning",
    solutions=(
        Solution(
            "reference",
            sha256="4ca2d6875f3769cee488d514f4bc1aa9232ed951252a88a48acfce486b96a77f",
            quick_score=1.0,
            files=((".", "solutions/balance_coins/ledgers/reference"),),
        ),
        Solution(
            "baseline/five_weighings",
            sha256="a2547945d9591cb9c369e33ee3514868dbc5a2d1d18435fda8dc583aa2969427",
            quick_score=0.4,
            files=((".", "solutions/balance_coins/ledgers/five_weighings"),),
        ),
        Solution(
            "baseline/unsealed",
            sha256="a710d934c4d311d845443eb9bbbfce1b8a0ab5a6eea09f96b2db858b89eebdb7",
            quick_score=0.0,
            base="reference",
            transforms=(_unseal,),
        ),
    ),
)
"""Committed public-key ledgers: the reference (two weighings), five weighings (0.4), the reference unsealed (0)."""
