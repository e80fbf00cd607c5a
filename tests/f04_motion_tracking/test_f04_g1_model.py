"""The actuated G1: 29 PD servos with mjlab's gains, and the PD steady state under gravity.

Closed form: a position servo at rest balances gravity, ``kp (q* - q) + tau_g = 0``, so its error is
``q* - q = -tau_g / kp`` with ``tau_g = sum_b axis . ((c_b - p) x m_b g)`` over the bodies b below
the joint (COM ``c_b``, mass ``m_b``; joint anchor ``p``).
"""

import math

import mujoco
import numpy as np
import pytest

from rle_tasks.f04_motion_tracking.public.g1 import g1_model, standing_qpos
from rle_tasks.f04_motion_tracking.public.g1_constants import G1, M7520_22, reflected_inertia


def test_constants_follow_the_formulae():
    a = reflected_inertia((0.489e-4, 0.109e-4, 0.738e-4), (1.0, 4.5, 5.0))
    assert a == pytest.approx(0.489e-4 * 22.5**2 + 0.109e-4 * 25 + 0.738e-4)
    w = 2 * math.pi * 10
    assert M7520_22.kp == pytest.approx(a * w**2) and M7520_22.kd == pytest.approx(4 * a * w)
    assert M7520_22.action_scale == pytest.approx(0.25 * 139.0 / (a * w**2))
    assert G1.dof == 29 and len(set(G1.joints)) == 29 and len(G1.tracked_bodies) == 14


def test_model_compiles_with_29_servos_in_joint_order():
    m = g1_model()
    assert (m.nq, m.nv, m.nu) == (36, 35, 29)
    for i, joint in enumerate(G1.joints):
        jid = m.actuator_trnid[i, 0]
        assert mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, jid) == joint
        assert m.actuator_gainprm[i, 0] == pytest.approx(G1.kp[i])
        assert m.actuator_biasprm[i, 1:3] == pytest.approx([-G1.kp[i], -G1.kd[i]])
        assert m.actuator_forcerange[i] == pytest.approx([-G1.effort[i], G1.effort[i]])
        assert m.dof_armature[m.jnt_dofadr[jid]] == pytest.approx(G1.armature[i])
    assert m.key("default").qpos == pytest.approx(standing_qpos())


def test_default_pose_stands_on_the_floor():
    m = g1_model()
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("default").id)
    mujoco.mj_forward(m, d)
    lowest = min(
        d.geom_xpos[g][2] - m.geom_size[g][0]
        for g in range(m.ngeom)
        if "foot" in (mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g) or "")
    )
    assert 0.0 <= lowest < 0.005  # capsule bottoms within 5 mm above the floor


def _gravity_torque(m, d, joint: str) -> float:
    jid = m.joint(joint).id
    axis, anchor = d.xaxis[jid], d.xanchor[jid]
    root = m.jnt_bodyid[jid]
    tau = 0.0
    for b in range(m.nbody):
        p = b
        while p not in (0, root):
            p = m.body_parentid[p]
        if p == root:
            force = m.body_mass[b] * m.opt.gravity
            tau += float(axis @ np.cross(d.xipos[b] - anchor, force))
    return tau


@pytest.mark.physics
def test_fixed_base_holds_the_default_pose_for_one_second_with_the_pd_steady_state_error():
    m = g1_model(timestep=0.002, fixed_base=True, floor=False)
    d = mujoco.MjData(m)
    d.qpos[:] = G1.default_pose
    d.ctrl[:] = G1.default_pose
    worst = 0.0
    for _ in range(500):  # the first second: held, no joint further than 20 deg from its target
        mujoco.mj_step(m, d)
        worst = max(worst, float(np.abs(np.asarray(G1.default_pose) - d.qpos).max()))
    assert worst < 0.35
    for _ in range(2000):  # 4 s more to come to rest (the servos are underdamped on the link inertia)
        mujoco.mj_step(m, d)
    mujoco.mj_forward(m, d)
    assert np.abs(d.qvel).max() < 1e-3
    err = np.asarray(G1.default_pose) - d.qpos
    for joint in (
        "left_elbow_joint",
        "right_shoulder_pitch_joint",
        "left_knee_joint",
        "right_ankle_pitch_joint",
    ):
        i = G1.joints.index(joint)
        expected = -_gravity_torque(m, d, joint) / G1.kp[i]
        assert abs(expected) > 1e-3, joint  # a loaded joint: the check can fail
        assert err[i] == pytest.approx(expected, rel=0.03), joint
