"""Rubric of 08-mobile-base: checkpoints, weights, the per-arm minimum and the cap, declared once.

Each arm-dependent checkpoint scores the minimum over the three arms (``per_variant`` holds each
arm's value). A failed structure checkpoint (validity) or a failed required load caps the reward at
0.15. The instruction's and the README's credit tables are ``RUBRIC.markdown_table()``.
"""

from __future__ import annotations

from rle_tasks.core.scoring import Cap, CheckpointSpec, Fraction, PassRule, Rubric
from rle_tasks.f08_mobile_base.batteries import (
    FORCE_ANGLE_MIN_DEG,
    LOSS_DURATION_S,
    LOSS_FRACTION,
    STATIC_MARGIN_MIN,
    TILT_MAX_DEG,
)
from rle_tasks.f08_mobile_base.public.scene import ARMS

LOAD_PASS = 0.5
"""``shelf_1kg`` (the required load) below this score is a failed load checkpoint [1]."""
DESIGN_NORMS = {
    "footprint_m2": (0.20, 0.60),
    "height_m": (0.30, 0.80),
    "base_mass_kg": (12.0, 40.0),
    "profile_length_m": (2.0, 8.0),
    "profile_cost_eur": (25.0, 110.0),
}
"""Design normalisation (good, bad) per metric [m^2, m, kg, m, EUR]: score = clip((bad - x) / (bad -
good), 0, 1), averaged over the five metrics."""

RUBRIC = Rubric(
    task_id="08-mobile-base",
    family="08",
    workflow="mechanical_design",
    variants=ARMS,
    checkpoints=(
        CheckpointSpec(
            "validity",
            0.15,
            "contract, catalog profiles, immutable parts, mount usable by all arms, no interpenetration",
            Fraction("1 when valid, else 0"),
        ),
        CheckpointSpec(
            "design_resources",
            0.35,
            "footprint, height, base mass, profile length and cost (smaller is better)",
            Fraction("mean of clip((bad - x) / (bad - good), 0, 1) over the five metrics"),
            pass_rule=PassRule(at=0.0, strict=True),
            threshold={k: {"good": g, "bad": b} for k, (g, b) in DESIGN_NORMS.items()},
        ),
        CheckpointSpec(
            "static_stability",
            0.15,
            "stowed, reach extremes and the targets at 0/1/2 kg: static margin, force angle, wheel load, tilt",
            Fraction("fraction of pose x payload cases that pass"),
            threshold={
                "margin_m": STATIC_MARGIN_MIN,
                "force_angle_deg": FORCE_ANGLE_MIN_DEG,
                "wheel_load_frac": LOSS_FRACTION,
            },
        ),
        CheckpointSpec(
            "dynamic_stability",
            0.20,
            "base accelerations, emergency stop, turning in place, arm swing with 2 kg: wheel load, tilt",
            Fraction("fraction of scenarios that pass"),
            threshold={
                "wheel_load_frac": LOSS_FRACTION,
                "loss_duration_s": LOSS_DURATION_S,
                "tilt_deg": TILT_MAX_DEG,
            },
        ),
        CheckpointSpec(
            "shelf_1kg",
            0.10,
            "shelf targets reached and held by the submitted controller with 1 kg",
            Fraction("fraction of targets held"),
        ),
        CheckpointSpec(
            "shelf_2kg",
            0.05,
            "shelf targets reached and held by the submitted controller with 2 kg",
            Fraction("fraction of targets held"),
        ),
    ),
    caps=(
        Cap("structure", 0.15, "the validity checkpoint fails"),
        Cap(
            "required_load",
            0.15,
            "the required 1 kg load fails: a pose in which the machine cannot stand with 0 or 1 kg, "
            f"or shelf_1kg below {LOAD_PASS:g} for some arm",
        ),
    ),
)
CAP = RUBRIC.cap("structure").value
WEIGHTS = {c.id: c.weight for c in RUBRIC.checkpoints}


def rubrics() -> dict[str, Rubric]:
    """Task id -> rubric (the family's one task)."""
    return {RUBRIC.task_id: RUBRIC}


STAGES = {
    "validity [%]": ("validity",),
    "resources [%]": ("design_resources",),
    "static [%]": ("static_stability",),
    "dynamic [%]": ("dynamic_stability",),
    "integration [%]": ("shelf_1kg", "shelf_2kg"),
}
"""The paper's design diagnostics: stage credit over stage weight (0.15, 0.35, 0.15, 0.20, 0.15)."""


def diagnostics(report) -> dict[str, float]:
    """Native diagnostics (results page): each stage's credit over its weight [%], before the gate cap,
    and the base's mass and footprint."""
    from rle_tasks.core.diagnostics import credit_over_weight

    out = credit_over_weight(report, STAGES)
    design = report.native_metrics.get("design") or {}
    names = (("base_mass_kg", "base mass [kg]"), ("footprint_m2", "footprint [m2]"))
    return out | {label: design[key] for key, label in names if key in design}
