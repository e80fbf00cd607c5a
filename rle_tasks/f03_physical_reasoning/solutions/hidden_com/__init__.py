"""Shipped agent programs of ``03-hidden-com`` and a runner that records their sealed ledgers.

As for ``03-balance-coins``, a submission is a session's sealed ledger (fresh nonce, opening time),
so the programs are shipped and ``record`` plays one on a metered session of the secret's instance.

| program | expected score | why |
|---|---|---|
| ``reference`` | 1.0 | wrist-torque probing in four box orientations, patch colour from the top view |
| ``random_answers`` | 0.0 (seed 0, public instance) | answers without probing: 1/4 correct on average |
"""

from __future__ import annotations

import importlib
from pathlib import Path

from rle_tasks.core.solutions import Solution, SolutionSet

PROGRAMS = ("reference", "random_answers")
SHIPPED = PROGRAMS
"""Programs whose public-key ledgers are committed (``ledgers/<name>/ledger.jsonl``, ``__main__`` records them)."""


def record(program: str, secret, dest: Path, camera_every: int = 10, **kwargs) -> Path:
    """Play ``program`` on the instance of ``secret``; write and return ``dest`` holding ``ledger.jsonl``.

    ``camera_every`` > 10 renders fewer views (the reference reads only the view after its reset).
    """
    import tempfile

    from rle_design.ledger import LedgerClient, LedgerServer
    from rle_tasks.core.devenv import ledger_key

    from ...hidden_com import BUDGET_STEPS
    from ...hidden_com_env import TASK_ID, make_env
    from ...hidden_com_verifier import LEDGER_FILE, instance

    if program not in PROGRAMS:
        raise ValueError(f"unknown program {program!r}. Programs: {', '.join(PROGRAMS)}")
    solve = importlib.import_module(f"{__name__}.{program}").solve
    dest = Path(dest)
    dest.mkdir(parents=True, exist_ok=True)
    (dest / LEDGER_FILE).unlink(missing_ok=True)
    with tempfile.TemporaryDirectory(prefix="rle-f03-") as tmp:
        server = LedgerServer(
            make_env(instance(secret), camera_every=camera_every),
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
            sha256="5f6e16ca5ba33adb8be89803fe256121427347f6c7aa8d8a8020511fed548f95",
            quick_score=1.0,
            files=((".", "solutions/hidden_com/ledgers/reference"),),
        ),
        Solution(
            "baseline/random_answers",
            sha256="f094031c905c23931627507b7bcde2c3ab97ba5b8b0f85eb17d4362db72da61e",
            quick_score=0.0,
            files=((".", "solutions/hidden_com/ledgers/random_answers"),),
        ),
        Solution(
            "baseline/unsealed",
            sha256="6b35178ffce428b6b64dc3aef75a742615a36632476dc9697d7ab541bcb693e2",
            quick_score=0.0,
            base="reference",
            transforms=(_unseal,),
        ),
    ),
)
"""Committed public-key ledgers: the reference (3/3), seeded random answers, the reference unsealed (0)."""
