"""Rubric of the family-04 tasks: the card's per-seed score, averaged over eight hidden seeds.

Per seed, with T the whole-body tracking score, U the survival fraction, J the action jerk and F the
fall indicator:

    s = 0.7 T + 0.3 U - 0.15 min(J / J_max, 1) - 0.05 F, clipped to [0, 1].

T is the mean over the clip's policy steps of ``(exp(-e_p / S_POS) + exp(-e_o / S_ORI) + exp(-e_w /
S_WORLD)) / 3`` with e_p the mean position error of the 14 tracked bodies to the re-anchored reference
[m], e_o their mean orientation error [rad] and e_w the world-frame torso position error [m]; steps
after a fall count 0. J is the root mean square over steps and
joints of the second difference of the PD targets [rad]. The derivations of S_POS, S_ORI and J_MAX are
in the README.
"""

from __future__ import annotations

from dataclasses import replace

from rle_tasks.core.scoring import Cap, CheckpointSpec, Deduction, Fraction, Rubric

from .constants import N_SEEDS, QUICK_SEEDS, TASK_IDS
from .public.evaluate import J_MAX, S_ORI, S_POS, S_WORLD, seed_score

__all__ = [
    "J_MAX",
    "N_SEEDS",
    "QUICK_SEEDS",
    "RUBRIC",
    "S_ORI",
    "S_POS",
    "S_WORLD",
    "TASK_IDS",
    "rubric",
    "seed_score",
]

JERK_PENALTY, FALL_PENALTY = 0.15, 0.05


RUBRIC = Rubric(
    task_id="04-dance",
    family="04",
    workflow="policy_learning",
    variants=tuple(f"seed{i + 1}" for i in range(N_SEEDS)),
    aggregate="variant_mean",
    checkpoints=(
        CheckpointSpec(
            "tracking",
            0.7,
            "whole-body tracking T: mean over steps of [exp(-e_p/0.1 m) + exp(-e_o/0.3 rad) + exp(-e_w/0.5 m)]/3",
            Fraction("T per seed"),
            combine="mean",
        ),
        CheckpointSpec(
            "survival", 0.3, "survival fraction U of the clip", Fraction("U per seed"), combine="mean"
        ),
    ),
    caps=(
        Cap("invalid", 0.0, "policy.onnx / policy_meta.json missing, malformed or over 10 M parameters"),
        Cap("smoke", 0.1, "smoke failure: different outputs for the same input, NaN, or an explosion in 1 s"),
    ),
    deductions=(
        Deduction("f04.jerk", JERK_PENALTY, "action jerk, times min(J / J_max, 1)"),
        Deduction("f04.fall", FALL_PENALTY, "the robot fell (a tracking termination bound)"),
    ),
    max_deduction=JERK_PENALTY + FALL_PENALTY,
)
"""The rubric of ``04-dance``; the other tasks differ only in ``task_id`` (``rubric``)."""


def rubric(task_id: str, n_seeds: int = N_SEEDS) -> Rubric:
    """The rubric of one task over its first ``n_seeds`` seeds."""
    return replace(RUBRIC, task_id=task_id, variants=RUBRIC.variants[:n_seeds])


def rubrics() -> dict[str, Rubric]:
    """Task id -> rubric, for every task of the family (the five clips share one)."""
    return dict.fromkeys(TASK_IDS, RUBRIC)


def diagnostics(report) -> dict[str, float]:
    """Native diagnostics (results page, the paper's native table): MPJPE [mm] and survival [%] of the
    clip, averaged over its seeds; the family row is their mean over the clips."""
    m = report.native_metrics
    return {
        label: m[key]
        for key, label in (("mpjpe_mm", "MPJPE [mm]"), ("survival_pct", "survival [%]"))
        if key in m
    }
