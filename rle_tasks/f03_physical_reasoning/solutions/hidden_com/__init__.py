"""Shipped agent programs of ``03-hidden-com`` and a runner that records their sealed ledgers.

As for ``03-balance-coins``, a submission is a session's sealed ledger (fresh nonce, opening time),
so the programs are shipped and ``record`` plays one on a metered session of the secret's instance.

| program | expected score | why |
|---|---|---|
| ``reference`` | 1.0 | wrist-torque probing in four box orientations, patch colour from the top view |
| ``random_answers`` | seeded guesses | answers without probing: 1/4 correct on average |
"""

from __future__ import annotations

import importlib
from pathlib import Path

PROGRAMS = ("reference", "random_answers")


def record(program: str, secret, dest: Path, camera_every: int = 10, **kwargs) -> Path:
    """Play ``program`` on the instance of ``secret``; write and return ``dest`` holding ``ledger.jsonl``.

    ``camera_every`` > 10 renders fewer views (the reference reads only the view after its reset).
    """
    from rle_design.ledger import MeteredSession
    from rle_tasks.core.devenv import ledger_key

    from ...hidden_com import BUDGET_STEPS
    from ...hidden_com_env import TASK_ID, make_env
    from ...hidden_com_verifier import LEDGER_FILE, instance

    if program not in PROGRAMS:
        raise ValueError(f"unknown program {program!r}. Programs: {', '.join(PROGRAMS)}")
    solve = importlib.import_module(f"{__name__}.{program}").solve
    dest = Path(dest)
    dest.mkdir(parents=True, exist_ok=True)
    session = MeteredSession(
        make_env(instance(secret), camera_every=camera_every),
        task_id=TASK_ID,
        budget=BUDGET_STEPS,
        key=ledger_key(secret, TASK_ID),
        ledger_path=dest / LEDGER_FILE,
    )
    solve(session, **kwargs)
    session.seal()
    return dest
