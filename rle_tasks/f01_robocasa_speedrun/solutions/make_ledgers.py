"""Build-time recorder of the shipped ledgers: ``python -m rle_tasks.f01_robocasa_speedrun.solutions.make_ledgers [TASK_ID ...]``.

Each ledger is recorded as an agent's would be: a ``LedgerServer`` serves the task's session under the
public development key (images rendered only for the level 1-2 references, the programs that read
them; they change neither the scenes nor their digests), the program drives it through a ``LedgerClient``, and the session is sealed. The
ledger is written gzipped to ``<ledger_dir(task id, name)>/ledger.jsonl.gz``; the script then verifies
each solution and prints the checksum and score to pin in ``PINS``.
"""

from __future__ import annotations

import gzip
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from rle_design.ledger import LedgerClient, LedgerError
from rle_tasks.core.runtime.devenv import record_solution
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret

from ..kitchens import BUDGET, KITCHEN_TASKS, LEVELS, STEP_BUDGET, KitchenTaskId, scenes
from . import LEDGER, agents

HERE = Path(__file__).resolve().parent
PUBLIC = Secret(PUBLIC_KEY, public=True)
BUDGET_TASK = "01-open-fridge-l1"
"""The one task whose ``budget_exhausted`` baseline is shipped (its ledger holds 50,000 actions)."""


def record(
    kitchen: KitchenTaskId,
    level: int,
    program: Callable[[LedgerClient], Any],
    dest: Path,
    images: bool = False,
) -> Path:
    """Serve the task's session under the public key, run ``program(client)``, seal; write
    ``dest/ledger.jsonl.gz``. ``images`` renders the cameras (programs that read them: levels 1-2)."""
    task_id = kitchen.task_id(level)
    with tempfile.TemporaryDirectory(prefix="rle-f01-") as tmp:
        env = scenes(kitchen, level, PUBLIC, image_size=(128, 128) if images else None)
        ledger = record_solution(
            env, program, Path(tmp) / LEDGER, PUBLIC, task_id, STEP_BUDGET, BUDGET.wall_time_s
        )
        dest.mkdir(parents=True, exist_ok=True)
        (dest / (LEDGER + ".gz")).write_bytes(gzip.compress(ledger.read_bytes(), mtime=0))
    return dest


def idle(client: LedgerClient) -> None:
    """Enter the evaluation phase and never act."""
    client.reset(evaluation=True)
    for _ in range(4):
        client.reset()


def budget_exhausted(client: LedgerClient) -> None:
    """Develop (holding still) until the server refuses a step; never evaluate."""
    client.reset()
    hold = np.zeros(12)
    hold[6] = hold[11] = -1.0
    while True:
        try:
            client.step(hold)
        except LedgerError as exc:
            if exc.code != "ledger.budget_exhausted":
                raise
            return


def programs(kitchen: KitchenTaskId, level: int) -> dict[str, Callable[[LedgerClient], Any]]:
    """The shipped programs of one task (name -> program)."""
    out: dict[str, Callable[[LedgerClient], Any]] = {}
    if agents.available(kitchen.task, level):
        out["reference"] = lambda c: agents.play(c, kitchen.task, level=level)
    out["baseline/idle"] = idle
    if kitchen.task_id(level) == BUDGET_TASK:
        out["baseline/budget_exhausted"] = budget_exhausted
    return out


def main(task_ids: list[str], only: set[str] | None = None) -> None:
    """Record the programs of ``task_ids`` (all when empty; only the solutions named in ``only``, when
    given), then print every solution's checksum and score."""
    from rle_tasks.core.registry import get_task
    from rle_tasks.core.report import artifact_sha256
    from rle_tasks.core.solutions import build
    from rle_tasks.core.task import VerifyContext

    from . import SolutionSet, _set, ledger_dir

    for kitchen in KITCHEN_TASKS:
        for level in LEVELS:
            task_id = kitchen.task_id(level)
            if task_ids and task_id not in task_ids:
                continue
            progs = programs(kitchen, level)
            for name, program in progs.items():
                if only and name not in only:
                    continue
                images = name == "reference" and level < 3
                record(kitchen, level, program, HERE / ledger_dir(task_id, name), images)
                print(f"{task_id} {name}: recorded", flush=True)
            names = list(progs) + (["baseline/tampered"] if "reference" in progs else [])
            sset: SolutionSet = _set(task_id, {n: ("", 0.0) for n in names})
            spec = get_task(task_id)
            for name in names:
                with tempfile.TemporaryDirectory() as tmp:
                    d = Path(tmp) / "s"
                    build(sset, name, d)
                    report = spec.verify(d, VerifyContext(secret=PUBLIC, quick=True))
                    print(
                        f'    "{name}": ("{artifact_sha256(d)}", {report.score!r}),  # {report.checkpoints[0].message}',
                        flush=True,
                    )


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--only=")]
    picked = {n for a in sys.argv[1:] if a.startswith("--only=") for n in a[7:].split(",")}
    main(args, picked or None)
