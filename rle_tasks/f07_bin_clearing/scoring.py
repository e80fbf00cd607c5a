"""Rubric of 07-bin-clearing: the card's per-pile score, clipped to [0, 1] and averaged over the piles.

Per pile, with f the cleared fraction, p the throughput [parts/min] = 60 x cleared / T (T the clear
makespan, 120 s when the pile is not cleared) and I the clean complete-clear indicator (every part
cleared with no floor, damage or bin event):

    s = 0.30 I + 0.35 h(f) + 0.20 min(p/10, 1) + 0.15 I min(p/15, 1)
        - 0.03 N_floor - 0.05 N_damage - 0.05 N_bin,

h(f) = f/6 for f <= 0.6, else 0.1 + 0.9 ((f - 0.6)/0.4)^3. Each checkpoint's per-pile score is the
bracketed factor (I, h(f), min(p/10, 1), I min(p/15, 1)); the rubric aggregates ``variant_mean``
with the event deduction of each pile, which floors the pile at 0 (the terms above never exceed 1).
"""

from __future__ import annotations

from dataclasses import replace

from rle_tasks.core.scoring import Cap, CheckpointSpec, Deduction, Fraction, Rubric

from .constants import N_PILES, QUICK_EPISODE_S, QUICK_PILES, TASK_ID
from .public.env import EPISODE_S

FLOOR_PENALTY, DAMAGE_PENALTY, BIN_PENALTY = 0.03, 0.05, 0.05


def h(f: float) -> float:
    """The card's clearance curve h(f)."""
    f = min(max(float(f), 0.0), 1.0)
    return f / 6.0 if f <= 0.6 else 0.1 + 0.9 * ((f - 0.6) / 0.4) ** 3


def throughput(cleared: int, makespan_s: float) -> float:
    """Parts per minute from the clear makespan [s] (the episode's length when the pile is not cleared)."""
    return 60.0 * cleared / makespan_s if makespan_s > 0 else 0.0


def pile_terms(summary: dict) -> dict[str, float]:
    """Checkpoint factors and deduction of one pile from its event summary."""
    n, cleared = int(summary["n_parts"]), int(summary["cleared"])
    f = cleared / n
    p = throughput(cleared, float(summary["makespan_s"]))
    clean = summary["N_floor"] == 0 and summary["N_damage"] == 0 and summary["N_bin"] == 0
    indicator = float(cleared == n and clean)
    deduction = (
        FLOOR_PENALTY * summary["N_floor"]
        + DAMAGE_PENALTY * summary["N_damage"]
        + BIN_PENALTY * summary["N_bin"]
    )
    return {
        "complete": indicator,
        "clearance": h(f),
        "throughput": min(p / 10.0, 1.0),
        "clean_throughput": indicator * min(p / 15.0, 1.0),
        "deduction": deduction,
        "p": p,
        "f": f,
    }


def pile_score(summary: dict) -> float:
    """The card's episode score of one pile, clipped to [0, 1]."""
    t = pile_terms(summary)
    s = 0.30 * t["complete"] + 0.35 * t["clearance"] + 0.20 * t["throughput"] + 0.15 * t["clean_throughput"]
    return min(max(s - t["deduction"], 0.0), 1.0)


RUBRIC = Rubric(
    task_id=TASK_ID,
    family="07",
    workflow="perception_estimation",
    variants=tuple(f"pile{i + 1}" for i in range(N_PILES)),
    aggregate="variant_mean",
    checkpoints=(
        CheckpointSpec(
            "complete",
            0.30,
            "clean complete clear I (every part cleared, no event)",
            Fraction("I per pile, 1 or 0"),
            combine="mean",
        ),  # fmt: skip
        CheckpointSpec(
            "clearance",
            0.35,
            "cleared fraction f",
            Fraction("h(f) = f/6 for f <= 0.6, else 0.1 + 0.9((f - 0.6)/0.4)^3"),
            combine="mean",
        ),  # fmt: skip
        CheckpointSpec(
            "throughput",
            0.20,
            "throughput p [parts/min] from the clear makespan (120 s if incomplete)",
            Fraction("min(p/10, 1)"),
            combine="mean",
        ),  # fmt: skip
        CheckpointSpec(
            "clean_throughput",
            0.15,
            "throughput of a clean complete clear",
            Fraction("I min(p/15, 1)"),
            combine="mean",
        ),  # fmt: skip
    ),
    caps=(
        Cap("unloadable", 0.0, "the policy/ package is missing or cannot be loaded (import, make_policy)"),
        Cap("smoke", 0.1, "the loaded policy fails the smoke test (reset and one act on a public pile)"),
    ),
    deductions=(
        Deduction("f07.floor", FLOOR_PENALTY, "per part on the floor"),
        Deduction("f07.damage", DAMAGE_PENALTY, "per damage event"),
        Deduction("f07.bin", BIN_PENALTY, "per hard bin impact"),
    ),
    max_deduction=1.0,
)
"""The rubric over the eight hidden piles."""


def rubric(n_piles: int) -> Rubric:
    """The rubric over the first ``n_piles`` piles (quick mode uses ``QUICK_PILES``)."""
    return replace(RUBRIC, variants=RUBRIC.variants[:n_piles])


__all__ = [
    "EPISODE_S",
    "N_PILES",
    "QUICK_EPISODE_S",
    "QUICK_PILES",
    "RUBRIC",
    "TASK_ID",
    "h",
    "pile_score",
    "pile_terms",
    "rubric",
]


def rubrics() -> dict[str, Rubric]:
    """Task id -> rubric (the family's one task)."""
    return {RUBRIC.task_id: RUBRIC}


def diagnostics(report) -> dict[str, float]:
    """Native diagnostics (results page, the paper's native table): clearance [%] and parts/min over the
    piles, and the parts damaged or dropped."""
    m = report.native_metrics
    out = {
        label: m[key]
        for key, label in (("clearance_pct", "clearance [%]"), ("parts_per_min", "parts/min"))
        if key in m
    }
    piles = [p.get("events") or {} for p in (m.get("piles") or {}).values() if isinstance(p, dict)]
    if piles:
        out["damaged"] = sum(e.get("N_damage", 0) for e in piles)
        out["on the floor"] = sum(e.get("N_floor", 0) for e in piles)
    return out
