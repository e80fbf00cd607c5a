"""Audit cases of family 01: one session ledger per card limit, signed with the audit secret's key."""

from __future__ import annotations

from typing import Any

import numpy as np

from rle_tasks.audit.case import Case
from rle_tasks.audit.ledger_limits import AUDIT_ATTEMPT, LimitCases, limit_cases

from .kitchens import ACTIONS_PER_TRIAL, BUDGET, EVAL_WALL_S, KITCHEN_TASKS, STEP_BUDGET, TRIALS, scenes

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
        "wall_time_s": BUDGET.wall_time_s,
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
    wall_time_s=BUDGET.wall_time_s,
    dev_reset={"scene": "pretrain/0/0", "phase": "development"},
    trials=TRIALS,
    actions_per_trial=ACTIONS_PER_TRIAL,
    evaluation_wall_time_s=EVAL_WALL_S,
    trial_reset=_trial_reset,
    out_of_range=_out_of_range,
)


def cases() -> list[Case]:
    """Family 01's ledger-limit cases (``rle audit-verifiers``)."""
    return limit_cases(SPEC, "f01")
