"""Agent programs of ``03-pocket-cube`` and a runner that records their sealed ledgers.

A submission is a session's sealed ledger (fresh nonce, opening time), so the programs are shipped and
``record`` plays one on a metered session of the secret's scramble. Every program acts only through
ordinary 14-D metered actions (``CartesianHelper`` with ``arm_size=7``) and reads no cube pose.

| program | expected score | why |
|---|---|---|
| ``reference`` | 1.0 | plans top-layer turns and whole-cube hand-offs for the public scramble and executes them with both hands, the cube in the air (``two_hands``): 4 quarter turns, optimum 4 |
| ``idle`` | 0.0 | the arms hold and the session is sealed: the cube stays scrambled on its stand |
| ``dropped`` | 0.0 | the right hand sweeps the cube off its stand; it ends on the table, not held |
| ``reset`` | 0.0 | a reset after the start abandons the attempt |
| ``forced_twist`` | 0.0 | a pitch the arm cannot follow forces the cube: one unclassified transition (cap 0.5), unsolved, on the table |
| ``top_turns`` | (building block) | quarter turns of the top layer by the right wrist against the stand, then the cube lifted |

Committed ledgers (``ledgers/<name>/ledger.jsonl``, recorded by ``__main__``): the ``SHIPPED`` programs on the
public scramble, and ``ledgers/reference_second`` = the reference on the second public scramble
(``U R U R'``; it verifies only against that scramble's scene, so the tests inject it).

"""

from __future__ import annotations

import importlib
from pathlib import Path

from rle_tasks.core.solutions import Solution, SolutionSet
from rle_tasks.f03_physical_reasoning.solutions import unseal

PROGRAMS = ("reference", "idle", "dropped", "reset", "forced_twist", "top_turns")
SHIPPED = ("reference", "idle", "dropped", "reset", "forced_twist")
"""Programs whose public-key ledgers are committed."""
SECOND = "reference_second"
"""Ledger directory of the reference on the second public scramble."""


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


def _ledgers(name: str) -> tuple[tuple[str, str], ...]:
    return ((".", f"solutions/pocket_cube/ledgers/{name}"),)


SOLUTIONS = SolutionSet(
    package="rle_tasks.f03_physical_reasoning",
    solutions=(
        Solution(
            "reference",
            sha256="6f4c3a9ec9f37eedfe65c837a0cb333116f4247b8a32b261d1a161522f6650d9",
            quick_score=1.0,
            files=_ledgers("reference"),
        ),
        Solution(
            "baseline/idle",
            sha256="e9e9bfa7feaafaf73044bc61b8205a4e143a1d8172894de8637710bf7ea9c3ad",
            quick_score=0.0,
            files=_ledgers("idle"),
        ),
        Solution(
            "baseline/dropped",
            sha256="55e2c6d6001f6c98d1e774d1f1c5bcd1f0ca481e3b7914d2ebf1954892ed2b66",
            quick_score=0.0,
            files=_ledgers("dropped"),
        ),
        Solution(
            "baseline/reset",
            sha256="c74cb5f7dd964aaa1d767f5a5b1174a7c3f4cfca59f7245c12c59afc0f645014",
            quick_score=0.0,
            files=_ledgers("reset"),
        ),
        Solution(
            "baseline/forced_twist",
            sha256="22c64894bcc8323eb8455850c429ae6a783792191f2f75018ccbb7f755497de1",
            quick_score=0.0,
            files=_ledgers("forced_twist"),
        ),
        Solution(
            "baseline/unsealed",
            sha256="2edc05bf7f7f0f795391cb56bc2b8854360c78ddd3aac5cb190d358997a7fc51",
            quick_score=0.0,
            base="reference",
            transforms=(unseal,),
        ),
    ),
)
"""Committed public-key ledgers: the reference (1.0), four baselines (0 each for its reason), the reference
unsealed (0)."""
