"""The whole-body QP expert (``solutions/expert_tracker.py``) on the G1's servos through ``TrackingEnv``, and the
DAgger distillation script's plumbing (``solutions/distil.py``)."""

from __future__ import annotations

import math
from pathlib import Path

import mujoco
import numpy as np

from rle_tasks.f04_motion_tracking.public.clip import Clip, clip_qpos
from rle_tasks.f04_motion_tracking.public.env import TrackingEnv
from rle_tasks.f04_motion_tracking.public.evaluate import EVAL_TIMESTEP
from rle_tasks.f04_motion_tracking.public.g1 import g1_model
from rle_tasks.f04_motion_tracking.solutions.expert_tracker import Expert

CLIPS = Path(__file__).resolve().parents[2] / "rle_tasks/f04_motion_tracking/assets/clips"


def _env(clip: Clip) -> TrackingEnv:
    return TrackingEnv(clip, timestep=EVAL_TIMESTEP, model=g1_model(timestep=EVAL_TIMESTEP, terrain=True))


def test_expert_tracks_the_dance_opening_on_the_nominal_robot() -> None:
    """First 3 s of the dance (weight shifts and the first steps): no termination, body position
    error (MPJPE) under 1 cm; the same episode twice gives the same actions (fresh solver per episode)."""
    clip = Clip.load(CLIPS / "dance.npz")
    expert = Expert(clip)
    runs = []
    for _ in range(2):
        env, actions, errors = _env(clip), [], []
        expert.reset()
        env.reset(0)
        for _ in range(150):
            actions.append(expert.action(env))
            _, _, term, _, info = env.step(actions[-1])
            assert not term, info.reason
            errors.append(info.body_pos_err)
        runs.append(np.array(actions))
        assert np.mean(errors) < 0.01
    np.testing.assert_array_equal(runs[0], runs[1])


def test_expert_standing_recovers_a_push_inside_the_capture_point_bound() -> None:
    """Standing clip (the dance's first frame held): a pelvis impulse dv with the capture point
    xi = x + dv / omega (omega = sqrt(g / z_com)) halfway from the COM to the soles' front edge is
    absorbed by the servos under the QP's targets, without a step (the feet stay within 1 cm)."""
    dance = Clip.load(CLIPS / "dance.npz")
    model = g1_model()
    clip = Clip.from_qpos(model, np.repeat(clip_qpos(dance)[:1], 150, axis=0), np.ones((150, 2), bool))
    expert = Expert(clip)
    env = _env(clip)
    env.reset(0)
    d, m = env.data, env.model
    feet = [m.body(f).id for f in ("left_ankle_roll_link", "right_ankle_roll_link")]
    front = max(
        float((d.xpos[b] + expert.soles[m.body(b).name] @ d.xmat[b].reshape(3, 3).T)[:, 0].max())
        for b in feet
    )
    x, z = d.subtree_com[1][0], d.subtree_com[1][2]
    dv = 0.5 * (front - x) * math.sqrt(9.81 / z)
    assert dv > 0.1
    feet0 = d.xpos[feet].copy()
    for k in range(140):
        if k == 10:
            d.qvel[0] += dv
        _, _, term, _, info = env.step(expert.action(env))
        assert not term, info.reason
    assert not expert.steps_taken
    assert np.abs(d.xpos[feet] - feet0).max() < 0.01
    mujoco.mj_forward(m, d)
    assert abs(d.subtree_com[1][0] - x) < 0.02
    assert np.linalg.norm(d.qvel[:2]) < 0.05


def test_distil_runs_end_to_end(tmp_path: Path) -> None:
    """Two DAgger iterations of one short episode each, one worker: a log and an exported policy."""
    from rle_tasks.f04_motion_tracking.public.contract import META, ONNX
    from rle_tasks.f04_motion_tracking.solutions import distil

    out = tmp_path / "d"
    distil.main(
        [str(CLIPS / "dance.npz"), str(out), "--iterations", "2", "--episodes", "1", "--steps", "5"]
        + ["--epochs", "1", "--hidden", "16", "--eval-seeds"]
    )
    assert (out / "policy" / ONNX).is_file() and (out / "policy" / META).is_file()
    assert len((out / "log.csv").read_text().splitlines()) == 3
