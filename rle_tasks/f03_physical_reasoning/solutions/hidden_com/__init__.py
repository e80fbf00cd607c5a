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
from rle_tasks.f03_physical_reasoning.solutions import unseal

PROGRAMS = ("reference", "random_answers")
SHIPPED = PROGRAMS
"""Programs whose public-key ledgers are committed (``ledgers/<name>/ledger.jsonl``, ``__main__`` records them)."""


def record(program: str, secret, dest: Path, camera_every: int = 10, **kwargs) -> Path:
    """Play ``program`` on the instance of ``secret``; write and return ``dest`` holding ``ledger.jsonl``.

    ``camera_every`` > 10 renders fewer views (the reference reads only the view after its reset).
    """
    from ...hidden_com import BUDGET_STEPS
    from ...hidden_com_env import TASK_ID, make_env
    from ...hidden_com_verifier import LEDGER_FILE, instance
    from .. import record_session

    if program not in PROGRAMS:
        raise ValueError(f"unknown program {program!r}. Programs: {', '.join(PROGRAMS)}")
    solve = importlib.import_module(f"{__name__}.{program}").solve
    dest = Path(dest)
    env = make_env(instance(secret), camera_every=camera_every)
    record_session(env, secret, TASK_ID, BUDGET_STEPS, dest / LEDGER_FILE, solve, **kwargs)
    return dest


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
            transforms=(unseal,),
        ),
    ),
)
"""Committed public-key ledgers: the reference (3/3), seeded random answers, the reference unsealed (0)."""
