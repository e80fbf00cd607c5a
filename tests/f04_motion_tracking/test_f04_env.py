"""Tracking environment: the 160-D observation against hand-built values, reward terms at zero error and
at one sigma, terminations, vector stepping."""

import math
from pathlib import Path

import mujoco
import numpy as np
import pytest

from rle_tasks.f04_motion_tracking.public.clip import Clip
from rle_tasks.f04_motion_tracking.public.env import TrackingEnv, VecTrackingEnv
from rle_tasks.f04_motion_tracking.public.g1_constants import G1
from rle_tasks.f04_motion_tracking.public.tracking import OBS_DIM, REWARD_TERMS, kernel, observation

CLIP = Path(__file__).resolve().parents[2] / "rle_tasks/f04_motion_tracking/assets/clips/dance.npz"
E1 = math.exp(-1.0)


def _yaw(a):
    return np.array([math.cos(a / 2), 0.0, 0.0, math.sin(a / 2)])


def test_observation_by_hand():
    """Robot anchor yawed +90 deg at (1, 2, 0.8); reference anchor at (1, 3, 0.8), unrotated.

    Anchor position error in the robot anchor frame: Rz(90)^T (0, 1, 0) = (1, 0, 0). Orientation error
    Rz(90)^T I = Rz(-90) = [[0, 1, 0], [-1, 0, 0], [0, 0, 1]]; its first two columns, row by row:
    (0, 1, -1, 0, 0, 0).
    """
    rjp, rjv = np.arange(29) * 0.01, np.arange(29) * -0.02
    jp, jv, act = np.full(29, 0.1), np.full(29, -0.3), np.linspace(-1, 1, 29)
    obs = observation(
        rjp, rjv, np.array([1.0, 3.0, 0.8]), _yaw(0.0), np.array([1.0, 2.0, 0.8]), _yaw(math.pi / 2),
        np.array([0.5, 0.0, 0.1]), np.array([0.0, 0.2, 0.0]), jp, jv, act,
    )  # fmt: skip
    assert obs.shape == (OBS_DIM,) == (160,)
    expected = np.concatenate(
        [rjp, rjv, [1, 0, 0], [0, 1, -1, 0, 0, 0], [0.5, 0, 0.1], [0, 0.2, 0], jp, jv, act]
    )
    assert obs == pytest.approx(expected, abs=1e-12)


def test_env_observation_layout_for_a_known_state():
    """Robot at frame 0 of the clip, then yawed 90 deg about its pelvis and moving at 1 m/s along world x:
    the IMU linear velocity in the pelvis frame is Rz(90)^T (1, 0, 0) = (0, -1, 0)."""
    clip = Clip.load(CLIP)
    env = TrackingEnv(clip)
    env.reset(0)
    d = env.data
    d.qpos[3:7] = _yaw(math.pi / 2)
    d.qvel[:] = 0.0
    d.qvel[0] = 1.0
    d.qvel[5] = 0.4  # pelvis-frame yaw rate
    d.qpos[7:] = np.asarray(G1.default_pose) + 0.05
    d.qvel[6:] = 0.2
    env.last_action = np.full(29, 0.3)
    mujoco.mj_forward(env.model, d)
    obs = env.observe()
    assert obs[:29] == pytest.approx(clip.joint_pos[0]) and obs[29:58] == pytest.approx(clip.joint_vel[0])
    assert obs[67:70] == pytest.approx([0.0, -1.0, 0.0], abs=1e-12)
    assert obs[70:73] == pytest.approx([0.0, 0.0, 0.4])
    assert obs[73:102] == pytest.approx(np.full(29, 0.05)) and obs[102:131] == pytest.approx(np.full(29, 0.2))
    assert obs[131:160] == pytest.approx(np.full(29, 0.3))
    # anchor orientation error: reference anchor R_ref seen from the robot anchor R = Rz(90) R_ref0
    r_ref = d.xmat[env.anchor].reshape(3, 3)
    ref = np.zeros(9)
    mujoco.mju_quat2Mat(ref, clip.body_quat_w[0, env.ref_anchor])
    assert obs[61:67] == pytest.approx((r_ref.T @ ref.reshape(3, 3))[:, :2].reshape(-1), abs=1e-9)


def test_kernel_is_one_at_zero_and_inverse_e_at_one_sigma():
    for term in REWARD_TERMS:
        assert kernel(0.0, term.sigma) == 1.0
        assert kernel(term.sigma**2, term.sigma) == pytest.approx(E1, rel=1e-12)


def _env_at_reference(frame=100):
    env = TrackingEnv(Clip.load(CLIP))
    env.reset(frame)
    return env


def test_reward_terms_are_one_on_the_reference():
    info = _env_at_reference().tracking()
    for term in REWARD_TERMS:
        assert info.terms[term.name] == pytest.approx(1.0, abs=1e-9)
    assert info.reason == ""


def test_reward_terms_at_one_sigma():
    # 0.3 m up: anchor and every body (the re-anchored reference keeps its own height) off by one sigma
    env = _env_at_reference()
    env.data.qpos[2] += 0.3
    mujoco.mj_forward(env.model, env.data)
    info = env.tracking()
    assert info.terms["anchor_pos"] == pytest.approx(E1, rel=1e-6)
    assert info.terms["body_pos"] == pytest.approx(E1, rel=1e-6)
    assert info.terms["body_ori"] == pytest.approx(1.0, abs=1e-9)
    assert info.reason == "anchor_height"  # 0.3 m > 0.25 m
    # +1 m/s along x on every body
    env = _env_at_reference()
    env.data.qvel[0] += 1.0
    mujoco.mj_forward(env.model, env.data)
    assert env.tracking().terms["body_lin_vel"] == pytest.approx(E1, rel=1e-6)
    # +3.14 rad/s about world z on every body
    env = _env_at_reference()
    w_local = env.data.xmat[1].reshape(3, 3).T @ np.array([0.0, 0.0, 3.14])
    env.data.qvel[3:6] += w_local
    mujoco.mj_forward(env.model, env.data)
    assert env.tracking().terms["body_ang_vel"] == pytest.approx(E1, rel=1e-6)
    # the whole robot yawed by 0.4 rad: anchor orientation one sigma off, bodies re-anchored (no error)
    env = _env_at_reference()
    q = np.zeros(4)
    mujoco.mju_mulQuat(q, _yaw(0.4), env.data.qpos[3:7].copy())
    env.data.qpos[3:7] = q
    mujoco.mj_forward(env.model, env.data)
    info = env.tracking()
    assert info.terms["anchor_ori"] == pytest.approx(E1, rel=1e-6)
    assert info.terms["body_ori"] == pytest.approx(1.0, abs=1e-9)


@pytest.mark.physics
def test_vector_env_steps_and_resets():
    vec = VecTrackingEnv(Clip.load(CLIP), 2, random_start=True)
    obs = vec.reset()
    assert obs.shape == (2, 160)
    done = 0
    for _ in range(100):
        obs, rew, term, trunc, infos = vec.step(np.zeros((2, 29)))
        assert np.isfinite(obs).all() and np.isfinite(rew).all()
        done += int(term.sum() + trunc.sum())
    assert done >= 2  # zero action falls within 100 steps (2 s); both environments were reset


def _floor_height(model, data, x, y):
    geom = np.array([-1], dtype=np.int32)
    return 1.0 - mujoco.mj_ray(
        model, data, np.array([x, y, 1.0]), np.array([0.0, 0.0, -1.0]), None, 1, -1, geom
    )


def test_terrain_roughness_stays_within_its_amplitude_and_is_flat_at_zero():
    from rle_tasks.f04_motion_tracking.public.g1 import g1_model
    from rle_tasks.f04_motion_tracking.public.perturb import Perturbation

    model = g1_model(terrain=True)
    Perturbation(terrain=0.02, terrain_seed=3).apply(model)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    h = np.array(
        [_floor_height(model, data, x, y) for x in np.linspace(1, 58, 30) for y in (-1, 0, 1)]
    )  # away from the robot
    assert h.min() >= -0.01 - 1e-9 and h.max() <= 0.01 + 1e-9 and h.std() > 0.002
    Perturbation().apply(model)
    mujoco.mj_forward(model, data)
    assert _floor_height(model, data, 5.0, 0.2) == pytest.approx(0.0, abs=1e-9)
