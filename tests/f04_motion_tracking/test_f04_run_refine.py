"""Run refinement (``run_refine``): its stance hip model against the feasibility check, the shipped run clip
passes the check, and the generator reproduces it (full battery: about 35 s of generation)."""

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


def test_shipped_run_clip_passes_the_check(full_battery):
    """The shipped run (2.2 m/s, refined) passes ``rle check-clip``: no joint above 90 % of its limit, no
    infeasible frame, every flight frame ballistic. Frames 240-300 (the worst joint, the left hip pitch at
    0.87, is at frame 264; three steps and three flights); the whole clip with RLE_FULL_BATTERY=1."""
    from rle_tasks.f04_motion_tracking.public.feasibility import check_clip

    clip = Clip.load(CLIPS / "run.npz")
    frames = None if full_battery else range(240, 300)
    s = check_clip(clip, frames=frames, model=g1_model()).summary()
    assert s["passed"], s
    assert s["flight_frames"] >= (149 if full_battery else 15)
    assert s["worst_ratio"] < 0.9


def test_refined_run_is_the_shipped_clip(full_battery, tmp_path):
    """``styles.run()`` regenerates the shipped run clip bit for bit as saved (deterministic; about 35 s)."""
    if not full_battery:
        pytest.skip("RLE_FULL_BATTERY=1: generates the refined run (about 35 s)")
    from rle_tasks.f04_motion_tracking.public.clipgen import generate
    from rle_tasks.f04_motion_tracking.public.styles import run

    generate(g1_model(), run()).save(tmp_path / "run.npz")
    clip, shipped = Clip.load(tmp_path / "run.npz"), Clip.load(CLIPS / "run.npz")
    assert np.array_equal(clip.joint_pos, shipped.joint_pos) and np.array_equal(
        clip.root_pos, shipped.root_pos
    )
    assert np.array_equal(clip.contacts, shipped.contacts)
