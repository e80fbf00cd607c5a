"""Audit cases of family 01: one session ledger per card limit, signed with the audit secret's key, and
ledgers that are no session of this task under this secret (the public rehearsal ledger, one signed for
another task or opened with another budget, a missing or linked ledger): each scores 0 with its code."""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

import numpy as np

from rle_design.ledger.records import LedgerWriter
from rle_tasks.audit.case import Case
from rle_tasks.audit.ledger_limits import AUDIT_ATTEMPT, LimitCases, limit_cases
from rle_tasks.core.solutions import materialise

from .constants import ACTIONS_PER_TRIAL, EVAL_WALL_S, STEP_BUDGET, TRIALS, WALL_TIME_S
from .kitchens import KITCHEN_TASKS, scenes

TASK = "01-turn-on-stove-l3"


def _scenes():
    from rle_tasks.audit.case import AUDIT_SECRET

    kitchen = next(k for k in KITCHEN_TASKS if k.task_id(3) == TASK)
    return scenes(kitchen, 3, AUDIT_SECRET.for_attempt(AUDIT_ATTEMPT), image_size=None)


def _open_meta() -> dict[str, Any]:
    return {
        "scene_set": _scenes().fingerprint(),
        "evaluation": {"trials": TRIALS, "actions_per_trial": ACTIONS_PER_TRIAL, "wall_time_s": EVAL_WALL_S},
        "budget": STEP_BUDGET,
        "wall_time_s": WALL_TIME_S,
    }


def _trial_reset(k: int) -> dict[str, Any]:
    return {"scene": f"target/{k}", "phase": "evaluation", "trial": k, "scene_sha256": "0" * 64}


def _out_of_range() -> tuple[list, dict]:
    """Trial 0 on its real target kitchen, its one action 50 times the range on every entry."""
    env = _scenes().scene("target/0")
    action = np.full(12, 50.0).tobytes().hex()
    records = [
        ("reset", {"scene": "pretrain/0/0", "phase": "development", "wall": 1.0}),
        ("reset", {**_trial_reset(0), "scene_sha256": env.fingerprint(), "wall": 2.0}),
        ("steps", {"actions": [action], "wall": 2.0}),
    ]
    trials = [{"scene": "target/0", "actions": 1, "success": False, "success_at": None}]
    return records, {"development_steps": 1, "trials": trials, "elapsed_s": 3.0}


SPEC = LimitCases(
    task_id=TASK,
    open_meta=_open_meta,
    action_size=12,
    budget=STEP_BUDGET,
    wall_time_s=WALL_TIME_S,
    dev_reset={"scene": "pretrain/0/0", "phase": "development"},
    trials=TRIALS,
    actions_per_trial=ACTIONS_PER_TRIAL,
    evaluation_wall_time_s=EVAL_WALL_S,
    trial_reset=_trial_reset,
    out_of_range=_out_of_range,
)


def _public_reference(d: Path) -> Path:
    """The shipped reference ledger, recorded under the public key: no use under a private secret."""
    shutil.copyfile(materialise(TASK, "reference") / "ledger.jsonl", d / "ledger.jsonl")
    return d


def _linked(d: Path) -> Path:
    (d / "ledger.jsonl").symlink_to(materialise(TASK, "reference") / "ledger.jsonl")
    return d


def _signed(task_id: str, budget: int):
    """A sealed ledger written with the audit secret's key of ``task_id``, opened as a session of
    ``budget`` development steps, with one reset."""

    def build(d: Path) -> Path:
        from rle_tasks.audit.case import AUDIT_SECRET
        from rle_tasks.core.runtime.devenv import ledger_key

        kitchen = next(k for k in KITCHEN_TASKS if k.task == "TurnOnStove")
        meta = {
            "scene_set": scenes(kitchen, 3, AUDIT_SECRET, image_size=None).fingerprint(),
            "evaluation": {"trials": 5, "actions_per_trial": 1000, "wall_time_s": 3600.0},
            "budget": budget,
            "wall_time_s": WALL_TIME_S,
        }
        w = LedgerWriter(d / "ledger.jsonl", ledger_key(AUDIT_SECRET, task_id), task_id, meta)
        w.append("reset", {"steps": 1, "time": 0.0, "scene": "pretrain/0/0", "phase": "development"})
        w.seal(1)
        return d

    return build


def cases() -> list[Case]:
    """Family 01's ledger cases (``rle audit-verifiers``)."""
    return [
        Case(
            "ledger/f01_public_rehearsal_ledger",
            TASK,
            "ledger.forged_key",
            _public_reference,
            wall_cap_s=30.0,
        ),
        Case("ledger/f01_linked_ledger", TASK, "ledger.missing", _linked, wall_cap_s=30.0),
        Case("ledger/f01_missing_ledger", TASK, "ledger.missing", lambda d: d, wall_cap_s=30.0),
        Case(
            "ledger/f01_other_task_key",
            TASK,
            "ledger.forged_key",
            _signed("01-turn-on-stove-l2", 50_000),
            wall_cap_s=30.0,
        ),
        Case(
            "ledger/f01_other_budget", TASK, "ledger.wrong_limits", _signed(TASK, 10_000_000), wall_cap_s=30.0
        ),
    ] + limit_cases(SPEC, "f01")
