"""Rubric of the family-05 tasks: success rate over a fixed episode set, zero on a failed replay.

The card: "Reward is success rate over the fixed episode set; missing episodes are failures. Failed
replay, artifact validation, or completion thresholds yield zero. No efficiency bonus." An episode is
*complete* when it ran to the task's success or to its horizon without a fault of the served policy
(``protocol.*``); LIBERO's fixed set is 500 episodes of which at least 475 must complete, i.e.
``COMPLETION`` = 95 %. A partial run (``--episodes N``) applies the same fraction to the episodes it
ran and scores successes over them; its report says partial and is never an official score.
"""

from __future__ import annotations

import math

from rle_tasks.core.scoring import Cap, CheckpointSpec, Fraction, PassRule, Rubric

from .constants import COMPLETION, EPISODE_SETS, EPISODES, OPEN_ID

TASK_ID = OPEN_ID
EPISODE_SET = EPISODES
"""LIBERO-10's official initial states: 10 tasks x 50 [1]."""

_ANY = PassRule(at=0.0, strict=True)
"""The success-rate checkpoint counts as passed when any episode succeeded."""


def required_complete(n_episodes: int) -> int:
    """Episodes of a run of ``n_episodes`` that must complete: ``ceil(0.95 n)`` (475 of 500)."""
    return math.ceil(COMPLETION * n_episodes - 1e-9)


def rubric(task_id: str, n_episodes: int) -> Rubric:
    """The rubric of ``task_id`` over a fixed set of ``n_episodes`` episodes."""
    need = required_complete(n_episodes)
    full = EPISODE_SETS[task_id]
    return Rubric(
        task_id=task_id,
        family="05",
        workflow="policy_learning",
        variants=("episodes",),
        checkpoints=(
            CheckpointSpec(
                "success_rate",
                1.0,
                f"successful episodes over the {n_episodes} episodes of the set (a missing or faulted "
                "episode is a failure)",
                Fraction("the success rate itself"),
                pass_rule=_ANY,
            ),
        ),
        caps=(
            Cap(
                "replay_failed",
                0.0,
                "the artifact check, the offline training or the checkpoint check failed",
            ),
            Cap(
                "incomplete",
                0.0,
                f"fewer than {need} of the {n_episodes} episodes completed (95 %, the card's "
                f"{required_complete(full)} of {full})",
            ),
        ),
    )


def rubrics() -> dict[str, Rubric]:
    """Task id -> rubric of its full episode set, for every task of the family."""
    return {tid: rubric(tid, n) for tid, n in EPISODE_SETS.items()}


def diagnostics(report) -> dict[str, float]:
    """Native diagnostics (results page): success over the evaluated episodes, their number, mean
    episode length and the recipe's training time on the verifier."""
    m = report.native_metrics
    out = {}
    if "success_rate" in m:
        out["success [%]"] = 100.0 * m["success_rate"]
    names = (("episodes_requested", "episodes"), ("mean_steps", "mean steps"), ("train_s", "training [s]"))
    out |= {label: m[key] for key, label in names if key in m}
    return out
