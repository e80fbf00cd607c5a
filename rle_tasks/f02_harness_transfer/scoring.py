"""Rubric of family 02 (card): the mean over five fresh agents of s_trial.

Per fresh agent, with b the conjuncts of the held-out task satisfied at the start, m the most satisfied
at once during its session and n their number: s_trial = 1 when the task's success predicate held,
else clip((m - b) / (n - b), 0, 1), and 0 without stage records (no reset) or when n = b. Missing
trials count 0. Binary success is reported beside (``native_metrics.successes``); development
efficiency adds nothing.
"""

from __future__ import annotations

import functools

from rle_tasks.core.scoring import CheckpointSpec, Fraction, Rubric


def _rubric(task_id: str, variant: str, checkpoint: CheckpointSpec) -> Rubric:
    return Rubric(
        task_id=task_id,
        family="02",
        workflow="interactive_control",
        variants=(variant,),
        checkpoints=(checkpoint,),
    )


@functools.cache
def rubric(task_id: str) -> Rubric:
    """The rubric of one group (all fifteen share it)."""
    return _rubric(
        task_id,
        "agents",
        CheckpointSpec(
            "transfer",
            1.0,
            "mean over five fresh agents of s_trial = 1 on success, else clip((m - b) / (n - b), 0, 1) "
            "(b: conjuncts satisfied at the start, m: most satisfied at once, n: conjuncts)",
            Fraction("mean s_trial of the five fresh agents (missing agents count 0)"),
        ),
    )


@functools.cache
def fresh_rubric(task_id: str) -> Rubric:
    """The rubric of one fresh agent run as a task of its own (``fresh.py``): its s_trial."""
    return _rubric(
        task_id,
        "agent",
        CheckpointSpec(
            "s_trial",
            1.0,
            "this fresh agent's s_trial = 1 on success, else clip((m - b) / (n - b), 0, 1)",
            Fraction("s_trial of the replayed session"),
        ),
    )


def rubrics() -> dict[str, Rubric]:
    """Task id -> rubric, for every task of the family."""
    from .groups import GROUPS

    return {g.task_id: rubric(g.task_id) for g in GROUPS}


def diagnostics(report) -> dict[str, float]:
    """Native diagnostics (results page): the fresh agents' success on the held-out task [%] and their
    successes."""
    m = report.native_metrics
    names = (("success_rate", "fresh-agent success [%]", 100.0), ("successes", "fresh-agent successes", 1.0))
    return {label: scale * m[key] for key, label, scale in names if key in m}
