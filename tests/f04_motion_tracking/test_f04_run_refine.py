"""Run refinement (``run_refine``): its stance hip model against the feasibility check, and the refined run
clip's check numbers (full battery: about 30 s of generation)."""

from pathlib import Path

import numpy as np
import pytest

from rle_tasks.f04_motion_tracking.public.clip import Clip
from rle_tasks.f04_motion_tracking.public.g1 import g1_model
from rle_tasks.f04_motion_tracking.public.g1_constants import G1

CLIPS = Path(__file__).resolve().parents[2] / "rle_tasks" / "f04_motion_tracking" / "assets" / "clips"


def test_stance_hip_torque_is_the_checks():
    """In single stance the foot wrench that balances the base is unique, so the hip pitch torque the
    refinement penalises is the check's (dance clip, which passes the check)."""
    from rle_tasks.f04_motion_tracking.public.feasibility import check_clip
    from rle_tasks.f04_motion_tracking.public.inverse_dynamics import stance_flags
    from rle_tasks.f04_motion_tracking.public.run_refine import base_wrench

    model = g1_model()
    clip = Clip.load(CLIPS / "dance.npz")
    w = base_wrench(model, clip)
    single = np.flatnonzero(stance_flags(clip.contacts).sum(axis=1) == 1)[::9]
    assert len(single) >= 6
    report = check_clip(clip, frames=single, model=model)
    for i, f in enumerate(single):
        leg = int(np.flatnonzero(clip.contacts[f])[0])
        tau = report.torque[i, G1.joints.index(("left", "right")[leg] + "_hip_pitch_joint")]
        assert w["hip_tau"][f] == pytest.approx(tau, abs=0.05), f
        assert w["hip_coef"][f, 0] > 0 and w["hip_coef"][f, 1] > 0


def test_refined_run_is_nearly_feasible(full_battery):
    """The refined run at 2.2 m/s, measured 2026-11-29: worst joint 0.95 of its limit (a knee, frame 667),
    3 frames over the 0.9 margin, 3 infeasible stance frames, 1 of 148 flight frames not ballistic; the
    shipped (keyed) run fails every flight frame and 2.3 times the ankle limit. Not yet passing."""
    if not full_battery:
        pytest.skip("RLE_FULL_BATTERY=1: generates the refined run (about 30 s)")
    from rle_tasks.f04_motion_tracking.public.clipgen import generate
    from rle_tasks.f04_motion_tracking.public.feasibility import check_clip
    from rle_tasks.f04_motion_tracking.public.run_refine import refined_plan

    model = g1_model()
    s = check_clip(generate(model, refined_plan("run")), model=model).summary()
    assert s["flight_frames"] > 140
    assert len(s["non_ballistic_flight_frames"]) <= 1
    assert len(s["infeasible_stance_frames"]) <= 3
    assert s["worst_ratio"] < 0.96 and len(s["frames_over_margin"]) <= 3
