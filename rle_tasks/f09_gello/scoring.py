"""Rubric of 09-gello: checkpoints, curves and deductions, declared once.

Every checkpoint scores a variant (robot) in [0, 1] with a linear curve: 1 at or better than the pass
value, 0 at or worse than the fail value, linear in between; a variant's samples (test poses,
copies) are averaged. Ten checkpoints of weight 0.1 form a variant's score; validity findings
deduct up to 0.10 (floor 0); the task score is the mean over the three variants. The instruction's
and the README's checkpoint tables are ``RUBRIC.markdown_table()``.
"""

from __future__ import annotations

from rle_design.scene import arm_ids
from rle_tasks.core.scoring import CheckpointSpec, Deduction, Linear, PassRule, Rubric

SERVO_LIMIT = 0.35
"""Stock servo torque limit [N m] (catalog ``torque_limit`` of the XL330-M288-T)."""

_HOLD = "largest joint drift within the hold time after release at rest, per test pose [rad]"
_BACK = "worst-joint breakaway torque, per test pose [N m]"
_BACK_EFFORT = (
    "worst-joint breakaway torque plus 3 rad/s^2 x the joint inertia the design adds over the stock "
    "leader, per test pose [N m]"
)
_EACH = PassRule(at=0.999, over="each")


def _cp(cid: str, group: str, metric: str, pass_value: float, fail_value: float) -> CheckpointSpec:
    return CheckpointSpec(
        cid, 0.1, metric, Linear(pass_value, fail_value), group=group, combine="mean", pass_rule=_EACH
    )


RUBRIC = Rubric(
    task_id="09-gello",
    family="09",
    workflow="mechanical_design",
    variants=arm_ids(),
    aggregate="variant_mean",
    checkpoints=(
        _cp(
            "motion_clearance",
            "motion clearance (10 %)",
            "fraction of hidden-grid poses where added parts collide with the arm, base or table",
            0.0,
            0.05,
        ),
        _cp(
            "passive_residual",
            "passive (30 %)",
            "95th percentile over the hidden grid of the worst-joint residual abs(g - tau_spring) [N m]",
            0.02,
            SERVO_LIMIT,
        ),
        _cp("passive_hold", "passive (30 %)", _HOLD + "; nominal leader, no feedforward", 0.005, 0.1),
        _cp(
            "passive_backdrive",
            "passive (30 %)",
            _BACK_EFFORT + "; nominal leader, no feedforward",
            0.03,
            SERVO_LIMIT,
        ),
        _cp(
            "reference_hold",
            "adapted reference arm (20 %)",
            _HOLD + "; stock-leader copy, adapted feedforward",
            0.005,
            0.1,
        ),
        _cp(
            "reference_backdrive",
            "adapted reference arm (20 %)",
            _BACK + "; stock-leader copy, adapted feedforward",
            0.03,
            SERVO_LIMIT,
        ),
        _cp(
            "combined_hold",
            "combined (40 %)",
            _HOLD + "; hidden copies, adapted feedforward clipped to 0.35 N m",
            0.005,
            0.1,
        ),
        _cp(
            "combined_backdrive",
            "combined (40 %)",
            _BACK_EFFORT + "; hidden copies, adapted feedforward clipped to 0.35 N m",
            0.03,
            SERVO_LIMIT,
        ),
        _cp(
            "servo_headroom",
            "combined (40 %)",
            "servo utilisation: hidden-grid max of the hidden copy's worst-joint residual / 0.35 N m",
            0.5,
            1.5,
        ),
        _cp(
            "push_recovery",
            "combined (40 %)",
            "creep in the last 0.5 s of 1 s after a 1 N, 50 ms horizontal handle push [rad]",
            0.005,
            0.1,
        ),
    ),
    deductions=(
        Deduction(
            "contract.over_mass",
            0.10,
            "device heavier than the 2.30 kg cap: 0.10 x (m - 2.30 kg) / 0.70 kg; above 3.00 kg refused",
        ),
        Deduction("contract.printability", 0.05, "an added mesh part not printable in PLA"),
    ),
    max_deduction=0.10,
)
CHECKPOINTS = RUBRIC.checkpoints
BY_ID = {c.id: c for c in CHECKPOINTS}


def mean_score(curve_id: str, values) -> float:
    """Mean of the per-sample scores of a checkpoint (a sample per test pose); 0 when there are none."""
    return BY_ID[curve_id].mean_score(values)


def rubrics() -> dict[str, Rubric]:
    """Task id -> rubric (the family's one task)."""
    return {RUBRIC.task_id: RUBRIC}


def diagnostics(report) -> dict[str, float]:
    """Native diagnostics (results page, the paper's design table): each arm's reward [%] (their mean is
    the task's reward) and the devices' mean mass."""
    m = report.native_metrics
    arms = m.get("variant_score") or {}
    out = {f"{arm} [%]": 100.0 * v for arm, v in arms.items()}
    masses = [
        m[arm]["device_mass_kg"]
        for arm in arms
        if isinstance(m.get(arm), dict) and "device_mass_kg" in m[arm]
    ]
    if masses:
        out["device mass [kg]"] = sum(masses) / len(masses)
    return out
