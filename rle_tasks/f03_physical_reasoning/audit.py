"""Audit cases of family 03: one session ledger per card limit of 03-cantilever, signed with the
audit secret's key; the same gate serves the family's other four tasks."""

from __future__ import annotations

from typing import Any

import numpy as np

from rle_tasks.audit.case import Case
from rle_tasks.audit.ledger_limits import AUDIT_ATTEMPT, LimitCases, limit_cases

from .cantilever.verifier import instance
from .constants import CANTILEVER_ID, STEP_BUDGET, WALL_TIME_S
from .scene import N_SUBSTEPS, make_env


def _env():
    from rle_tasks.audit.case import AUDIT_SECRET

    return make_env(instance(AUDIT_SECRET.for_attempt(AUDIT_ATTEMPT)).pieces, images=False)


def _open_meta() -> dict[str, Any]:
    return {
        "budget": STEP_BUDGET,
        "wall_time_s": WALL_TIME_S,
        "model_sha256": _env().fingerprint(),
        "n_substeps": N_SUBSTEPS,
        "timestep": 0.002,
    }


def _out_of_range() -> tuple[list, dict]:
    """A reset and one action 50 times the range on every entry."""
    action = np.full(12, 50.0).tobytes().hex()
    return [("reset", {"wall": 1.0}), ("steps", {"actions": [action], "wall": 1.0})], {"elapsed_s": 2.0}


SPEC = LimitCases(
    task_id=CANTILEVER_ID,
    open_meta=_open_meta,
    action_size=12,
    budget=STEP_BUDGET,
    wall_time_s=WALL_TIME_S,
    dev_reset={},
    out_of_range=_out_of_range,
)


def cases() -> list[Case]:
    """Family 03's ledger-limit cases (``rle audit-verifiers``)."""
    return limit_cases(SPEC, "f03")
