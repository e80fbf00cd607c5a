"""Heel rise and world-path swings (``MotionPlan.heel_rise``, ``MotionPlan.cartesian_swing``; not yet used by a
shipped clip): a foot on its toes pivots on its toe line, and the run keyed with both keeps every collision
point above the floor, where its joint-space swings go through it."""

from dataclasses import replace

import mujoco
import numpy as np
import pytest

from rle_tasks.f04_motion_tracking.public.g1 import g1_model, standing_qpos
from rle_tasks.f04_motion_tracking.public.ik import LegIK
from rle_tasks.f04_motion_tracking.public.inverse_dynamics import PENETRATION_TOL, InverseDynamics
from rle_tasks.f04_motion_tracking.public.keying import TOE, _kinematic, _on_toes, foot_ground_height
from rle_tasks.f04_motion_tracking.public.motion_plan import Stance
from rle_tasks.f04_motion_tracking.public.styles import refined_plan


@pytest.fixture(scope="module")
def model():
    return g1_model()


def _sole(solver, q):
    solver.data.qpos[:] = q
    mujoco.mj_kinematics(solver.model, solver.data)
    b = solver.feet[0]
    return solver.data.xpos[b] + solver.soles[0] @ solver.data.xmat[b].reshape(3, 3).T


def test_a_foot_on_its_toes_pivots_on_the_toe_line(model):
    """Solved by the leg IK for pitch 0 and 0.4 rad: the toe vertices (x = TOE) stay where they were, every
    vertex rises by (TOE - x) sin(pitch) (rigid rotation about the toe line on the floor)."""
    solver, ik, z0 = InverseDynamics(model), LegIK(model), foot_ground_height(model)
    q = standing_qpos()
    foot = _sole(solver, q)[:, :2].mean(axis=0)
    stance = Stance(0, 0.0, 1.0, (float(foot[0]) + 0.05, float(foot[1])), 0.0)
    soles = []
    for pitch in (0.0, 0.4):
        pos, yaw, p = _on_toes(stance, z0, pitch)
        solved, err = ik.solve(q.copy(), [(pos, yaw, True, p), None])
        assert err < 1e-4
        soles.append(_sole(solver, solved))
    local = solver.soles[0]
    toe = np.isclose(local[:, 0], TOE, atol=1e-3)
    assert toe.sum() >= 2 and soles[1][toe] == pytest.approx(soles[0][toe], abs=2e-4)
    rise = (TOE - local[:, 0]) * np.sin(0.4)
    assert soles[1][:, 2] - soles[0][:, 2] == pytest.approx(rise, abs=5e-4)


def _lowest(model, clip):
    solver = InverseDynamics(model)
    out = []
    for f in range(clip.frames):
        solver.data.qpos[:] = np.concatenate([clip.root_pos[f], clip.root_quat[f], clip.joint_pos[f]])
        mujoco.mj_kinematics(solver.model, solver.data)
        out.append(solver.lowest_point()[0])
    return np.array(out)


def test_world_path_swings_with_heel_rise_keep_the_run_above_the_floor(model):
    """The run plan keyed (not refined): joint-space swings (as shipped) go more than 15 cm under the floor;
    with heel rise (0.12 s, 0.6 rad), world-path swings and footholds the pelvis passes at 40 % of a stance at
    speed (``plant``; 50 %: the late swing foot is beyond the reach of a flat foot) no point goes below
    -PENETRATION_TOL (lowest -2.9 mm)."""
    plan = refined_plan("run")
    shipped = _lowest(model, _kinematic(model, plan))
    assert shipped.min() < -0.15
    toes = replace(
        refined_plan("run", plant=0.4), heel_rise=(0.12, 0.6), cartesian_swing=True, bump_power=2.0
    )
    assert _lowest(model, _kinematic(model, toes)).min() > -PENETRATION_TOL
