"""Rubric of the family's tasks (card): R = s [0.80 + 0.20 (1 - d / 50,000)].

``s`` is the number of successful evaluation trials over five (a missing trial counts as a failure),
``d`` the charged development steps. The two checkpoints are the card's two terms: ``success``
(weight 0.80, score s) and ``efficiency`` (weight 0.20, score s (1 - d / 50,000)), so their credits sum
to R. A missing, unsealed or unverifiable ledger makes the report invalid with score 0. ``passed`` is
informational: ``success`` at s >= 0.8 (four of five trials), ``efficiency`` at >= 0.5.
"""

from __future__ import annotations

import functools

from rle_tasks.core.scoring import CheckpointSpec, Fraction, PassRule, Rubric

STEP_BUDGET = 50_000


@functools.cache
def rubric(task_id: str) -> Rubric:
    """The rubric of one family-01 task (all fifteen share it)."""
    return Rubric(
        task_id=task_id,
        family="01",
        workflow="interactive_control",
        variants=("trials",),
        checkpoints=(
            CheckpointSpec(
                "success",
                0.80,
                "s: evaluation trials whose success predicate held after some action, out of 5 target kitchens",
                Fraction("s, the fraction of the five trials that succeeded (missing trials fail)"),
                pass_rule=PassRule(at=0.8),
            ),
            CheckpointSpec(
                "efficiency",
                0.20,
                "s (1 - d / 50,000): success scaled by the unused share of the development budget (d charged steps)",
                Fraction("s (1 - d / 50,000)"),
                pass_rule=PassRule(at=0.5),
            ),
        ),
    )


def rubrics() -> dict[str, Rubric]:
    """Task id -> rubric, for every task of the family."""
    from .kitchens import KITCHEN_TASKS, LEVELS

    return {k.task_id(level): rubric(k.task_id(level)) for k in KITCHEN_TASKS for level in LEVELS}


def diagnostics(report) -> dict[str, float]:
    """Native diagnostics (results page): success over the five target kitchens, actions per trial and
    the development steps the session spent."""
    m = report.native_metrics
    trials = m.get("trials") or []
    out = {}
    if trials:
        out["success [%]"] = 100.0 * sum(bool(t.get("success")) for t in trials) / len(trials)
        out["actions per trial"] = sum(t.get("actions", 0) for t in trials) / len(trials)
    if "development_steps" in m:
        out["development steps"] = m["development_steps"]
    return out
