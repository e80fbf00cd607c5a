"""Run refinement (``run_refine``): its stance hip model against the feasibility check, the shipped run clip
fails the check (its swing feet go through the floor), and the generator reproduces it (full battery: about
35 s of generation)."""

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


def test_shipped_run_clip_fails_the_check_through_the_floor(full_battery):
    """The shipped run (2.2 m/s, refined) meets the torque and residual criteria of ``rle check-clip`` (worst
    joint the left hip pitch at 0.87, frame 264) only with its swing feet through the floor: mid-swing the
    knee is straight and the foot goes up to 19 cm below the floor in frames 240-300 (21 cm in the whole
    clip), and the check had let the floor push on the swing shins (knee links within 2 cm of the floor).
    Frames 240-300 (three steps); the whole clip with RLE_FULL_BATTERY=1."""
    from rle_tasks.f04_motion_tracking.public.feasibility import check_clip

    clip = Clip.load(CLIPS / "run.npz")
    frames = None if full_battery else range(240, 300)
    report = check_clip(clip, frames=frames, model=g1_model())
    s = report.summary()
    assert not s["passed"] and s["lowest_point"] < -0.15 and s["lowest_body"] in G1.feet
    assert s["worst_ratio"] < 0.9 and not s["infeasible_stance_frames"]  # what the old verdict saw
    assert len(s["through_floor_frames"]) > (400 if full_battery else 30)
    knees = [i for i, c in enumerate(report.contacts) if any("knee" in b for b in c)]
    assert len(knees) > 0  # the swing shins' contacts with the floor: each where the leg is through it
    assert set(report.frames[knees].tolist()) <= set(s["through_floor_frames"])


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
