"""Shipped agent programs of ``03-hidden-com`` and a runner that records their sealed ledgers.

As for ``03-balance-coins``, a submission is a session's sealed ledger (fresh nonce, opening time),
so the programs are shipped and ``record`` plays one on a metered session of the secret's instance.

| program | expected score | why |
|---|---|---|
| ``reference`` | 1.0 | wrist-torque probing in four box orientations, patch colour from the top view |
| ``random_answers`` | 0.0 (seed 0, public instance) | answers without probing: 1/4 correct on average |
| ``late_answers`` | 1/3 | the reference's probing, idle 12,000 steps after box 0: boxes 1 and 2 refused as late |
"""

from __future__ import annotations

import importlib
from pathlib import Path

from rle_tasks.f03_physical_reasoning.solutions import committed, solution_set, unsealed
from rle_tasks.f03_physical_reasoning.solutions.oracle import reference_program_oracle

PROGRAMS = ("reference", "random_answers", "late_answers")
SHIPPED = PROGRAMS
"""Programs whose public-key ledgers are committed (``ledgers/<name>/ledger.jsonl``, ``__main__`` records them)."""


def record(program: str, secret, dest: Path, camera_every: int = 10, **kwargs) -> Path:
    """Play ``program`` on the instance of ``secret``; write and return ``dest`` holding ``ledger.jsonl``.

    ``camera_every`` > 10 renders fewer views (the reference reads only the view after its reset).
    """
    from rle_tasks.core.runtime.devenv import record_solution

    from ...constants import HIDDEN_COM_ID, HIDDEN_COM_STEPS, HIDDEN_COM_WALL_TIME_S
    from ...hidden_com.env import make_env
    from ...hidden_com.verifier import LEDGER_FILE, instance

    if program not in PROGRAMS:
        raise ValueError(f"unknown program {program!r}. Programs: {', '.join(PROGRAMS)}")
    solve = importlib.import_module(f"{__name__}.{program}").solve
    dest = Path(dest)
    env = make_env(instance(secret), camera_every=camera_every)
    play = lambda c: solve(c, **kwargs)  # noqa: E731
    record_solution(
        env, play, dest / LEDGER_FILE, secret, HIDDEN_COM_ID, HIDDEN_COM_STEPS, HIDDEN_COM_WALL_TIME_S
    )
    return dest


SOLUTIONS = solution_set(
    committed(
        "reference",
        "95a391143c6e63b5ab7d99e8b3899372434f55c4b1ee44769601790276daa5fc",
        1.0,
        "solutions/hidden_com/ledgers/reference",
    ),
    committed(
        "baseline/random_answers",
        "357c35a3ba2e5d562c9d7d4122516196a0574c2eb6b98b286b8af4c8631d670b",
        0.0,
        "solutions/hidden_com/ledgers/random_answers",
    ),
    committed(
        "baseline/late_answers",
        "c2fcc3b6cb225bb2d3f980ee6ad2577f06c7b886a7c6ca4d7d2760ec1c5595d3",
        1 / 3,
        "solutions/hidden_com/ledgers/late_answers",
    ),
    unsealed("c979e83fa0f0d121abe1a332741e977d52786d939e022f8e4381bf7ff95905b9"),
)
"""Committed public-key ledgers: the reference (3/3), seeded random answers, the reference unsealed (0)."""


harbor_oracle = reference_program_oracle(__file__)
"""The Harbor oracle: ``reference.py`` (it reads only what agents get) plays through the sidecar."""
