"""Rubrics of the family-03 tasks built in this package (tower, cantilever); each one checkpoint.

A missing, unsealed or altered ledger (or one that does not replay) makes the report invalid with
score 0 and the ledger's reason; otherwise the score is the card's ratio clipped to [0, 1].
"""

from __future__ import annotations

import math

from rle_tasks.core.scoring import CheckpointSpec, Fraction, Rubric

TOWER_ID = "03-tower"
CANTILEVER_ID = "03-cantilever"
PZ4 = (15.0 - 4.0 * math.sqrt(2.0)) / 8.0
"""Paterson-Zwick optimal overhang of four blocks, in block lengths (1.16789)."""

TOWER_RUBRIC = Rubric(
    task_id=TOWER_ID,
    family="03",
    workflow="interactive_control",
    variants=("scene",),
    checkpoints=(
        CheckpointSpec(
            "height",
            1.0,
            "settled height of the robot-free tower above the table / H* [1]",
            Fraction("height / H*, clipped to [0, 1]"),
        ),
    ),
)
CANTILEVER_RUBRIC = Rubric(
    task_id=CANTILEVER_ID,
    family="03",
    workflow="interactive_control",
    variants=("scene",),
    checkpoints=(
        CheckpointSpec(
            "overhang",
            1.0,
            "settled overhang beyond the table edge along its normal / ((15 - 4 sqrt 2)/8 L) [1]",
            Fraction("overhang / (1.16789 L), clipped to [0, 1]"),
        ),
    ),
)
RUBRICS = {TOWER_ID: TOWER_RUBRIC, CANTILEVER_ID: CANTILEVER_RUBRIC}
RUBRIC = TOWER_RUBRIC
"""The family's first rubric (the family-shape test reads ``RUBRIC``)."""


def rubrics() -> dict[str, Rubric]:
    """Task id -> rubric, for every task of the family (three are declared beside their verifiers)."""
    from . import balance_verifier, hidden_com_verifier
    from .cube import verifier as cube_verifier

    out = dict(RUBRICS)
    for module in (balance_verifier, hidden_com_verifier, cube_verifier):
        out[module.RUBRIC.task_id] = module.RUBRIC
    return out


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
