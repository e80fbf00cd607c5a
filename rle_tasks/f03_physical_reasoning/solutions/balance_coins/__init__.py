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

PROGRAMS = {"reference": 1.0, "five_weighings": 0.4, "wrong_cube": 0.0}
"""Program -> expected score (any instance)."""


def record(program: str, secret, dest: Path) -> Path:
    """Play ``program`` on the instance of ``secret``; write and return ``dest`` holding ``ledger.jsonl``."""
    from rle_design.ledger import MeteredSession
    from rle_tasks.core.devenv import ledger_key

    from ...balance import BUDGET_STEPS
    from ...balance_env import TASK_ID, make_env
    from ...balance_verifier import LEDGER_FILE, instance

    if program not in PROGRAMS:
        raise ValueError(f"unknown program {program!r}. Programs: {', '.join(PROGRAMS)}")
    solve = importlib.import_module(f"{__name__}.{program}").solve
    dest = Path(dest)
    dest.mkdir(parents=True, exist_ok=True)
    session = MeteredSession(
        make_env(instance(secret), image_size=None),
        task_id=TASK_ID,
        budget=BUDGET_STEPS,
        key=ledger_key(secret, TASK_ID),
        ledger_path=dest / LEDGER_FILE,
    )
    solve(session)
    session.seal()
    return dest
