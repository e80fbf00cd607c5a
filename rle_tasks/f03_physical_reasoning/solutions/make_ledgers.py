"""Build-time generator of the shipped ledgers: ``python -m rle_tasks.f03_physical_reasoning.solutions.make_ledgers``.

Each ledger is recorded as an agent's would be: a ``LedgerServer`` serves the public development
instance (the public key, ``privileged=True``, see ``agents``), the agent program drives it through a
``LedgerClient`` with the movement helper, and the session is sealed. The ledgers are committed; the
solutions' checksums pin them (``python -m rle_tasks.core.solutions`` prints the new pins).
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from rle_design.ledger import LedgerClient
from rle_tasks.core.runtime.devenv import record_solution
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret

from ..constants import CANTILEVER_ID, STEP_BUDGET, TOWER_ID, WALL_TIME_S
from ..scene import CONFIG, make_env
from . import agents

HERE = Path(__file__).resolve().parent
PUBLIC = Secret(PUBLIC_KEY, public=True)

Program = Callable[[Callable[[Any], dict], dict], object]


def record(task_id: str, pieces: tuple, program: Program, dest: Path) -> int:
    """Serve the public instance, run ``program(step, obs)`` through a client, seal; returns steps used."""
    steps: list[int] = []

    def solve(client: LedgerClient) -> None:
        program(client.step, client.reset())
        steps.append(client.info()["steps_used"])

    env = make_env(pieces, privileged=True, images=False)
    record_solution(env, solve, dest, PUBLIC, task_id, STEP_BUDGET, WALL_TIME_S)
    return steps[0]


def cantilever_ledgers() -> None:
    from ..cantilever import verifier as cantilever

    inst = cantilever.instance(PUBLIC)
    for name, scale in (("reference", 0.93), ("baseline/overreach", 1.15)):

        def program(step: Callable, obs: dict, scale: float = scale) -> object:
            return agents.harmonic_cantilever(step, obs, CONFIG.edge_x, CONFIG.top_z, scale=scale)

        steps = record(CANTILEVER_ID, inst.pieces, program, HERE / name / "cantilever" / "ledger.jsonl")
        print(f"03-cantilever {name}: {steps} steps")


def tower_ledgers() -> None:
    from ..tower import verifier as tower

    inst = tower.instance(PUBLIC)
    plan = tower.reference_plan(inst)
    for name, knock in (("reference", False), ("baseline/knocked_over", True)):

        def program(step: Callable, obs: dict, knock: bool = knock) -> object:
            return agents.tower(step, obs, plan, tower.BUILD_SPOT, CONFIG.top_z, knock_over=knock)

        steps = record(TOWER_ID, inst.pieces, program, HERE / name / "tower" / "ledger.jsonl")
        print(f"03-tower {name}: {steps} steps")


if __name__ == "__main__":
    which = sys.argv[1:] or ["cantilever", "tower"]
    if "cantilever" in which:
        cantilever_ledgers()
    if "tower" in which:
        tower_ledgers()
