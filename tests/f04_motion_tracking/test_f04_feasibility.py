"""Clip feasibility check (inverse dynamics with contact wrenches) on closed cases.

(a) Static pose: with q' = q'' = 0 the equations of motion reduce to ``g(q) = S^T tau + sum_c J_c^T w_c``
    (``g``: generalised gravity, ``J_c``: the contact body's 6 x nv Jacobian at its origin, world axes;
    ``w_c``: its wrench, force and moment about that origin). So the joint torques are
    ``tau = g_joints(q) - sum_c J_c,joints^T w_c`` and the base rows ``g_base(q) - sum_c J_c,base^T w_c``
    vanish; checked against Pinocchio's ``computeGeneralizedGravity`` and frame Jacobians, independent of
    MuJoCo's inverse dynamics. Newton: the contact forces add up to the weight, ``sum_c f_c = m g``.
(b) A push-off at several g in one frame (feet planted, legs solved by IK) is flagged at that frame,
    naming the joint over its limit; the same motion at 0.2 g passes.
(c) A flight frame (no contact) passes only when the base accelerates with gravity: the base residual
    of a rigid free fall with ``z'' = a`` is ``m (a + 9.81)`` along z.
Also: the centre of pressure stays on the sole polygon; a pelvis on the floor pushes without friction; a
body more than ``PENETRATION_TOL`` below the floor fails the frame.
"""

import json

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from rle_tasks.f04_motion_tracking.public import feasibility as fz
from rle_tasks.f04_motion_tracking.public import inverse_dynamics as idyn
from rle_tasks.f04_motion_tracking.public.clip import Clip
from rle_tasks.f04_motion_tracking.public.g1 import FOOT_FRICTION, g1_model, g1_model_path, standing_qpos
from rle_tasks.f04_motion_tracking.public.g1_constants import G1
from rle_tasks.f04_motion_tracking.public.ik import LegIK
from rle_tasks.f04_motion_tracking.public.soles import sole_polygon

DT = 0.02


@pytest.fixture(scope="module")
def model():
    return g1_model()


@pytest.fixture(scope="module")
def solver(model):
    return idyn.InverseDynamics(model)


def _pinocchio():
    pm = pin.buildModelFromMJCF(str(g1_model_path()))
    return pm, pm.createData()


def _pin_q(q):
    return np.concatenate([q[:3], q[4:7], q[3:4], q[7:]])  # pinocchio: x y z qx qy qz qw


def _static_pose():
    """Default stance, yawed 0.3 rad, arms and waist moved (an asymmetric load)."""
    q = standing_qpos()
    q[3:7] = [np.cos(0.15), 0.0, 0.0, np.sin(0.15)]
    for name, angle in (
        ("waist_yaw_joint", 0.3),
        ("left_shoulder_pitch_joint", -1.2),
        ("right_elbow_joint", 1.4),
    ):
        q[7 + G1.joints.index(name)] = angle
    return q


def test_static_pose_torques_are_pinocchio_gravity_torques_given_the_contact_wrench(solver, model):
    q = _static_pose()
    res = solver.solve(q, np.zeros(model.nv), np.zeros(model.nv), np.array([True, True]))
    assert set(res.wrenches) == set(G1.feet) and res.solver == "qpoases"
    assert np.linalg.norm(res.residual) < 1e-8  # base equations met

    pm, pd = _pinocchio()
    assert tuple(pm.names[2:]) == G1.joints  # same joint (and velocity) order as MuJoCo
    qp = _pin_q(q)
    g = pin.computeGeneralizedGravity(pm, pd, qp)
    pin.computeJointJacobians(pm, pd, qp)
    pin.updateFramePlacements(pm, pd)
    contact = np.zeros(pm.nv)
    for body, w in res.wrenches.items():
        jac = pin.getFrameJacobian(pm, pd, pm.getFrameId(body), pin.LOCAL_WORLD_ALIGNED)
        contact += jac.T @ w
    assert np.abs(g[:6] - contact[:6]).max() < 1e-6  # base: gravity balanced by the feet
    assert res.torque == pytest.approx(g[6:] - contact[6:], abs=1e-6)
    total = sum(w[:3] for w in res.wrenches.values())
    assert total == pytest.approx([0.0, 0.0, mujoco.mj_getTotalmass(model) * 9.81], abs=1e-6)
    assert abs(idyn.MASS - mujoco.mj_getTotalmass(model)) < 1e-3  # the unit of the tolerances
    for w in res.wrenches.values():  # every foot pushes, inside its friction pyramid
        assert w[2] > 0 and abs(w[0]) + abs(w[1]) <= FOOT_FRICTION * w[2] + 1e-9


def test_centre_of_pressure_stays_on_the_sole(solver, model):
    q = _static_pose()
    res = solver.solve(q, np.zeros(model.nv), np.zeros(model.nv), np.array([True, True]))
    d = solver.data
    for i, body in enumerate(G1.feet):
        w, b = res.wrenches[body], model.body(body).id
        sole = sole_polygon(model, body)
        rot = d.xmat[b].reshape(3, 3)
        z = (d.xpos[b] + rot @ sole[0])[2] - d.xpos[b][2]  # sole plane relative to the body origin
        # moment about the origin of a force f at the CoP p (on the sole plane): m = (p - o) x f + m_z e_z
        p = d.xpos[b][:2] + np.array([z * w[0] - w[4], w[3] + z * w[1]]) / w[2]
        local = rot[:2, :2].T @ (p - d.xpos[b][:2])
        edges = np.roll(sole[:, :2], -1, axis=0) - sole[:, :2]  # counter-clockwise polygon
        to_p = local - sole[:, :2]
        assert (edges[:, 0] * to_p[:, 1] - edges[:, 1] * to_p[:, 0] >= -1e-9).all(), (i, local)


def _push_off_clip(model, accel, push=5, frames=9, z0=0.66):
    """Crouched double stance; in frame ``push`` the pelvis gains ``accel * DT`` of upward speed."""
    ik = LegIK(model)
    d = mujoco.MjData(model)
    q = standing_qpos()
    d.qpos[:] = q
    mujoco.mj_kinematics(model, d)
    targets = [(d.xpos[model.body(f).id].copy(), 0.0, True) for f in G1.feet]
    qs = []
    for t in range(frames):
        q[2] = z0 + accel * DT * max(t - push, 0) * DT
        q, err = ik.solve(q, targets)
        assert err < 1e-4
        qs.append(q.copy())
    return Clip.from_qpos(model, np.array(qs), np.ones((frames, 2), bool))


def test_push_off_at_several_g_is_flagged_naming_the_joint(model):
    clip = _push_off_clip(model, 6 * 9.81)
    report = fz.check_clip(clip, model=model)
    joint, frame, ratio = report.worst
    assert not report.passed and frame == 5 and ratio > 1.0
    assert report.over_limit.tolist() == [5]
    assert len(report.infeasible) == 0  # the floor can push that hard: the joints cannot
    row = next(r for r in report.joint_table() if r["joint"] == joint)
    assert (
        row["frame"] == 5
        and row["frames_over_limit"] == 1
        and row["max_torque"] > G1.effort[G1.joints.index(joint)]
    )
    assert joint.split("_", 1)[1] in {"hip_pitch_joint", "knee_joint", "ankle_pitch_joint"}

    # Newton at the push frame: the contact forces add up to m (c'' + g), with c'' the COM acceleration
    # Pinocchio computes from the same q, q', q'' (the pelvis does not rotate, so MuJoCo's world-frame
    # base velocity and Pinocchio's local one coincide)
    solver = idyn.InverseDynamics(model)
    qpos = np.concatenate([clip.root_pos, clip.root_quat, clip.joint_pos], 1)
    qv, qa = idyn.finite_differences(solver.model, qpos, DT)
    assert np.abs(qv[5, 3:6]).max() == 0 and clip.root_quat[5] == pytest.approx([1, 0, 0, 0])
    res = solver.solve(clip.qpos(5), qv[5], qa[5], np.array([True, True]))
    pm, pd = _pinocchio()
    pin.centerOfMass(pm, pd, _pin_q(clip.qpos(5)), qv[5], qa[5])
    expected = mujoco.mj_getTotalmass(model) * (pd.acom[0] + [0, 0, 9.81])
    assert sum(w[:3] for w in res.wrenches.values()) == pytest.approx(expected, rel=1e-6)

    gentle = fz.check_clip(_push_off_clip(model, 0.2 * 9.81), model=model)
    assert gentle.passed and gentle.worst[2] < ratio / 3


def _free_fall_clip(model, accel, frames=5):
    q = np.tile(_static_pose(), (frames, 1))
    t = np.arange(frames) * DT
    q[:, 2] = 2.0 + 1.0 * t + 0.5 * accel * t**2  # high above the floor: no body touches it
    return Clip.from_qpos(model, q, np.zeros((frames, 2), bool))


def test_flight_passes_only_when_ballistic(model):
    ballistic = fz.check_clip(_free_fall_clip(model, -9.81), model=model)
    assert ballistic.passed and len(ballistic.flight) == 5
    assert np.abs(ballistic.residual).max() < 1e-6  # float64 qpos: exact for quadratic motion

    slow = fz.check_clip(_free_fall_clip(model, -5.0), model=model)
    assert not slow.passed and slow.summary()["non_ballistic_flight_frames"] == list(range(5))
    mass = mujoco.mj_getTotalmass(model)
    assert slow.residual[:, :3] == pytest.approx(np.tile([0, 0, mass * (-5.0 + 9.81)], (5, 1)), abs=1e-6)


def test_bodies_on_the_floor_push_without_friction(solver, model):
    """A pelvis lowered onto the floor (feet not in stance) is a contact; non-foot capsules have
    ``condim`` 1 in the model, so their contact force is normal only."""
    q = standing_qpos()
    q[2] = 0.16  # pelvis sphere (radius 0.07, 0.08 below the origin): lowest point 1 cm up
    res = solver.solve(q, np.zeros(model.nv), np.zeros(model.nv), np.array([False, False]))
    assert "pelvis" in res.wrenches and not set(G1.feet) & set(res.wrenches)
    for w in res.wrenches.values():
        assert w[0] == 0 and w[1] == 0 and w[2] >= 0
    weight = mujoco.mj_getTotalmass(model) * 9.81
    assert sum(w[2] for w in res.wrenches.values()) + res.residual[2] == pytest.approx(weight)


def test_bodies_through_the_floor_fail(model):
    """A free fall (ballistic: no base residual) whose feet lie ``depth`` below the floor: a rigid
    translation moves every point alike, so the lowest point of frame t is ``-depth - g (t - 0.04)^2 / 2`` (up to 7.8 mm deeper) when the
    standing pose, lowest at ``z_s`` (3 mm: the soles' capsules), is lowered by ``z_s + depth``; beyond
    ``PENETRATION_TOL`` (1 cm) every frame fails, within it the clip passes."""
    stand = standing_qpos()
    solver = idyn.InverseDynamics(model)
    solver.data.qpos[:] = stand
    mujoco.mj_kinematics(solver.model, solver.data)
    z_s, body = solver.lowest_point()
    assert 0 <= z_s < 0.005 and body in G1.feet
    t = np.arange(5) * DT
    for depth, through in ((0.015, True), (0.0, False)):
        q = np.tile(stand, (5, 1))
        q[:, 2] = stand[2] - z_s - depth - 0.5 * 9.81 * (t - 0.04) ** 2
        report = fz.check_clip(Clip.from_qpos(model, q, np.zeros((5, 2), bool)), model=model)
        assert np.abs(report.residual).max() < 1e-3 and len(report.over_margin) == 0  # ballistic, light
        assert report.lowest == pytest.approx(-depth - 0.5 * 9.81 * (t - 0.04) ** 2, abs=1e-4)
        assert report.summary()["through_floor_frames"] == (list(range(5)) if through else [])
        assert report.passed is not through
        assert report.summary()["lowest_body"] in G1.feet


def test_a_stance_sole_pushes_only_where_it_touches(solver, model):
    """The robot standing, pitched rigidly by 0.2 rad about the soles' front edge (heels up): a stance sole's
    contact points are exactly its polygon's vertices that the rotation leaves below FLOOR_HEIGHT (those within
    FLOOR_HEIGHT / sin 0.2 = 10 cm of the front edge: the toe region); lifted 3 cm, a stance-flagged sole has none and the weight m g is the base
    residual (no contact holds it)."""
    q = standing_qpos()
    stance = np.array([True, True])
    d = solver.data
    d.qpos[:] = q
    mujoco.mj_kinematics(solver.model, d)
    verts = [d.xpos[b] + solver.soles[i] @ d.xmat[b].reshape(3, 3).T for i, b in enumerate(solver.feet)]
    assert len(solver.contacts(stance)) == 2 and all(
        len(c.points) == len(v) for c, v in zip(solver.contacts(stance), verts)
    )
    toe = np.array([max(v[:, 0].max() for v in verts), 0.0, min(v[:, 2].min() for v in verts)])
    theta = 0.2
    rot = np.array(
        [[np.cos(theta), 0, np.sin(theta)], [0, 1, 0], [-np.sin(theta), 0, np.cos(theta)]]
    )  # heels up
    pitched = q.copy()
    pitched[:3] = toe + rot @ (q[:3] - toe)
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, rot.flatten())
    pitched[3:7] = quat
    d.qpos[:] = pitched
    mujoco.mj_kinematics(solver.model, d)
    for c, v in zip(solver.contacts(stance), verts):
        moved = toe + (v - toe) @ rot.T
        expected = moved[moved[:, 2] < idyn.FLOOR_HEIGHT]
        assert 0 < len(expected) < len(v) and c.points == pytest.approx(expected, abs=1e-9)
        assert (expected[:, 0] > toe[0] - idyn.FLOOR_HEIGHT / np.sin(theta) - 0.01).all()  # the toe region
    lifted = q.copy()
    lifted[2] += 0.03
    res = solver.solve(lifted, np.zeros(model.nv), np.zeros(model.nv), stance)
    assert res.wrenches == {}
    assert res.residual[:3] == pytest.approx([0, 0, mujoco.mj_getTotalmass(model) * 9.81], rel=1e-6)


def test_stance_flags_cover_the_frames_next_to_a_contact_change():
    c = np.array([[1, 0], [1, 0], [0, 0], [0, 0], [0, 1]], bool)
    assert idyn.stance_flags(c).astype(int).tolist() == [[1, 0], [1, 0], [1, 0], [0, 1], [0, 1]]


def test_check_clip_command_writes_a_report(tmp_path, model, capsys):
    from rle_tasks.cli import main

    path = tmp_path / "stand.npz"
    Clip.from_qpos(model, np.tile(standing_qpos(), (3, 1)), np.ones((3, 2), bool)).save(path)
    assert main(["check-clip", str(path), "--json", str(tmp_path / "r.json")]) == 0
    out = capsys.readouterr().out
    report = json.loads((tmp_path / "r.json").read_text())
    assert report["passed"] is True and "PASS" in out
    assert len(report["joints"]) == 29 and report["joints"][0]["joint"] == G1.joints[0]


def test_check_clip_command_names_the_frames_under_the_floor(tmp_path, model, capsys):
    """A standing clip lowered 3 cm (feet 30 mm under the floor, beyond PENETRATION_TOL = 10 mm) fails,
    and the printed lines name its frames and the lowest body."""
    from rle_tasks.cli import main

    q = np.tile(standing_qpos(), (3, 1))
    q[:, 2] -= 0.03
    path = tmp_path / "sunk.npz"
    Clip.from_qpos(model, q, np.ones((3, 2), bool)).save(path)
    assert main(["check-clip", str(path)]) == 0
    out = capsys.readouterr().out
    assert "frames with a point more than 10 mm under the floor: 0-2" in out
    assert "ankle_roll_link" in out and "FAIL" in out
