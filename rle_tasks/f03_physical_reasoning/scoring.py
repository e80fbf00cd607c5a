"""Rubrics of the family's tasks, by task id: each task subpackage declares its own (``<task>/scoring.py``).

A missing, unsealed or altered ledger (or one that does not replay) makes a report invalid with score 0
and the ledger's reason (``session.invalid_report``); otherwise each task scores by its card.
"""

from __future__ import annotations

from rle_tasks.core.scoring import Rubric

from .balance import scoring as balance
from .cantilever import scoring as cantilever
from .cube import scoring as cube
from .hidden_com import scoring as hidden_com
from .tower import scoring as tower

RUBRICS: dict[str, Rubric] = {
    **tower.RUBRICS,
    **cantilever.RUBRICS,
    **balance.RUBRICS,
    **cube.RUBRICS,
    **hidden_com.RUBRICS,
}


def rubrics() -> dict[str, Rubric]:
    """Task id -> rubric, for every task of the family."""
    return dict(RUBRICS)


def diagnostics(report) -> dict[str, float]:
    """Native diagnostics (results page): interaction steps, and each task's own count (weighings,
    turns against the optimum, answers right, the cantilever's block length)."""
    m = report.native_metrics
    names = {
        "steps": "steps",
        "weighings": "weighings",
        "turns": "cube turns",
        "optimal": "optimal turns",
        "correct": "answers right",
        "block_length_m": "block length [m]",
    }
    return {label: m[key] for key, label in names.items() if key in m}
