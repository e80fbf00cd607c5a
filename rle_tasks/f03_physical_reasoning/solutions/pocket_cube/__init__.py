"""Agent programs of ``03-pocket-cube`` and a runner that records their sealed ledgers.

A submission is a session's sealed ledger (fresh nonce, opening time), so the programs are shipped and
``record`` plays one on a metered session of the secret's scramble. Every program acts only through
ordinary 14-D metered actions (``CartesianHelper`` with ``arm_size=7``) and reads no cube pose.

| program | expected score | why |
|---|---|---|
| ``idle`` | 0.0 | the arms hold and the session is sealed: the cube stays scrambled on its stand |
| ``dropped`` | 0.0 | the right hand sweeps the cube off its stand; it ends on the table, not held |
| ``reset`` | 0.0 | a reset after the start abandons the attempt |
| ``top_turns`` | (building block) | quarter turns of the top layer by the right wrist, then the cube lifted |

No reference solve exists yet, so no ``SolutionSet`` is declared (the shipped-solution tests require a
reference first); the tests record and verify these programs directly.
"""

from __future__ import annotations

import importlib
from pathlib import Path

PROGRAMS = ("reference", "idle", "dropped", "reset", "top_turns")


def record(program: str, secret, dest: Path, camera_every: int = 100_000, inst=None, **kwargs) -> Path:
    """Play ``program`` on the scramble of ``secret``; write and return ``dest`` holding ``ledger.jsonl``.

    ``camera_every`` renders the front view only that often (no program reads it; the scene and its
    fingerprint do not change). ``inst`` replaces the secret's scramble (tests of the verifier's
    positive path on a shallow scramble; such a ledger verifies only against that scramble).
    """
    from ...cube.env import make_env
    from ...cube.scene import TASK_ID, instance
    from ...cube.task import BUDGET_STEPS
    from ...cube.verifier import LEDGER_FILE
    from .. import record_session

    if program not in PROGRAMS:
        raise ValueError(f"unknown program {program!r}. Programs: {', '.join(PROGRAMS)}")
    solve = importlib.import_module(f"{__name__}.{program}").solve
    dest = Path(dest)
    env = make_env(instance(secret) if inst is None else inst, camera_every=camera_every)
    record_session(env, secret, TASK_ID, BUDGET_STEPS, dest / LEDGER_FILE, solve, **kwargs)
    return dest
