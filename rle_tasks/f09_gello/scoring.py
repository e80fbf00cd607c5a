"""Checkpoints, thresholds and scoring curves of 09-gello (the README table is generated from here).

Every checkpoint scores a variant (robot) in [0, 1] with a linear curve: 1 at or better than the pass
value, 0 at or worse than the fail value, linear in between. Ten checkpoints of weight 0.1 each form
a variant's score; validity shortfalls deduct up to ``MAX_DEDUCTION`` (floor 0); the task score is
the mean over the three variants.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SERVO_LIMIT = 0.35
"""Stock servo torque limit [N m] (catalog ``torque_limit`` of the XL330-M288-T)."""
MAX_DEDUCTION = 0.10
DEDUCTIONS = {"contract.over_mass": 0.10, "contract.printability": 0.05, "contract.point_mass": 0.05}


@dataclass(frozen=True)
class Curve:
    """Linear scoring curve of one checkpoint.

    Attributes:
        id: Checkpoint id.
        group: Rubric group of the task card.
        metric: What is measured, with units.
        pass_value: Value scoring 1.
        fail_value: Value scoring 0.
    """

    id: str
    group: str
    metric: str
    pass_value: float
    fail_value: float

    def score(self, value: float) -> float:
        if not np.isfinite(value):
            return 0.0
        s = (self.fail_value - value) / (self.fail_value - self.pass_value)
        return float(np.clip(s, 0.0, 1.0))


_HOLD = "largest joint drift within the hold time after release at rest, per test pose [rad]"
_BACK = "worst-joint breakaway torque, per test pose [N m]"
CHECKPOINTS: tuple[Curve, ...] = (
    Curve(
        "motion_clearance",
        "motion clearance (10 %)",
        "fraction of workspace-grid poses where added parts collide with the arm, base or table",
        0.0,
        0.05,
    ),
    Curve(
        "passive_residual",
        "passive (30 %)",
        "95th percentile over the grid of the worst-joint residual abs(g - tau_spring) [N m]",
        0.02,
        SERVO_LIMIT,
    ),
    Curve("passive_hold", "passive (30 %)", _HOLD + "; nominal leader, no feedforward", 0.005, 0.1),
    Curve(
        "passive_backdrive", "passive (30 %)", _BACK + "; nominal leader, no feedforward", 0.03, SERVO_LIMIT
    ),
    Curve(
        "reference_hold",
        "adapted reference arm (20 %)",
        _HOLD + "; stock-leader copy, adapted feedforward",
        0.005,
        0.1,
    ),
    Curve(
        "reference_backdrive",
        "adapted reference arm (20 %)",
        _BACK + "; stock-leader copy, adapted feedforward",
        0.03,
        SERVO_LIMIT,
    ),
    Curve(
        "combined_hold",
        "combined (40 %)",
        _HOLD + "; hidden copies, adapted feedforward clipped to 0.35 N m",
        0.005,
        0.1,
    ),
    Curve(
        "combined_backdrive",
        "combined (40 %)",
        _BACK + "; hidden copies, adapted feedforward clipped to 0.35 N m",
        0.03,
        SERVO_LIMIT,
    ),
    Curve(
        "servo_headroom",
        "combined (40 %)",
        "servo utilisation: grid max of the hidden copy's worst-joint residual / 0.35 N m",
        0.5,
        1.5,
    ),
    Curve(
        "push_recovery",
        "combined (40 %)",
        "creep in the last 0.5 s of 1 s after a 1 N, 50 ms horizontal handle push [rad]",
        0.005,
        0.1,
    ),
)
WEIGHT = 1.0 / len(CHECKPOINTS)
BY_ID = {c.id: c for c in CHECKPOINTS}


def mean_score(curve_id: str, values: list[float] | np.ndarray) -> float:
    """Mean of the per-sample scores (a sample per test pose); 0 when there are none."""
    values = list(np.ravel(values))
    if not values:
        return 0.0
    return float(np.mean([BY_ID[curve_id].score(v) for v in values]))


def deduction(codes: list[str]) -> float:
    """Validity deduction of a variant: sum of the distinct codes' deductions, capped."""
    return min(MAX_DEDUCTION, sum(DEDUCTIONS.get(c, 0.0) for c in set(codes)))


def markdown_table() -> str:
    """Checkpoint table for the README."""
    rows = [
        "| checkpoint | group | weight | metric | pass (score 1) | fail (score 0) |",
        "|---|---|---|---|---|---|",
    ]
    for c in CHECKPOINTS:
        rows.append(
            f"| `{c.id}` | {c.group} | {WEIGHT:.2f} | {c.metric} | {c.pass_value:g} | {c.fail_value:g} |"
        )
    return "\n".join(rows)
