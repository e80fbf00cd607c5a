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

from rle_tasks.f03_physical_reasoning.solutions import committed, solution_set, unsealed
from rle_tasks.f03_physical_reasoning.solutions.oracle import reference_program_oracle

PROGRAMS = {"reference": 1.0, "five_weighings": 0.4, "wrong_cube": 0.0}
"""Program -> expected score (any instance)."""
SHIPPED = ("reference", "five_weighings")
"""Programs whose public-key ledgers are committed (``ledgers/<name>/ledger.jsonl``, ``__main__`` records them)."""


def record(program: str, secret, dest: Path, **kwargs) -> Path:
    """Play ``program`` on the instance of ``secret``; write and return ``dest`` holding ``ledger.jsonl``."""
    from rle_tasks.core.runtime.devenv import record_solution

    from ...balance.env import make_env
    from ...balance.verifier import LEDGER_FILE, instance
    from ...constants import BALANCE_ID, STEP_BUDGET, WALL_TIME_S

    if program not in PROGRAMS:
        raise ValueError(f"unknown program {program!r}. Programs: {', '.join(PROGRAMS)}")
    solve = importlib.import_module(f"{__name__}.{program}").solve
    dest = Path(dest)
    env = make_env(instance(secret), image_size=None)
    record_solution(
        env, lambda c: solve(c, **kwargs), dest / LEDGER_FILE, secret, BALANCE_ID, STEP_BUDGET, WALL_TIME_S
    )
    return dest


SOLUTIONS = solution_set(
    committed(
        "reference",
        "b434297a905314e90ad9eaf2a83c6eda078fc40cbaaac0700bbb73df1627321c",
        1.0,
        "solutions/balance_coins/ledgers/reference",
    ),
    committed(
        "baseline/five_weighings",
        "0197242c019f4d2526639faf0b7e7719ff28340939041475c60c1f614083c193",
        0.4,
        "solutions/balance_coins/ledgers/five_weighings",
    ),
    unsealed("c692a98faf010684eb2afec1f32395b5da0fb91acb3b997fd8da72fb379442e5"),
)
"""Committed public-key ledgers: the reference (two weighings), five weighings (0.4), the reference unsealed (0)."""


harbor_oracle = reference_program_oracle(__file__)
"""The Harbor oracle: ``reference.py`` (it reads only what agents get) plays through the sidecar."""
