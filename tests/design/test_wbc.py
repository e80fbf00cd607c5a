"""Whole-body QP controller (``rle_design.control.wbc``) on mjlab's 29-DoF G1 MJCF (read directly, as
the simulator and Pinocchio both parse it): static torques against Pinocchio's RNEA, push recovery
within the capture-point bound, servo targets."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import mujoco
import numpy as np

from rle_design.control.wbc import WholeBodyQP, servo_targets
from rle_design.control.wbc_reference import motion_reference
from rle_design.control.wbc_tasks import FrameTask, WbcGains

G = 9.81
FEET = ("left_ankle_roll_link", "right_ankle_roll_link")
# Sole corners in the ankle-roll frame [m] (the foot capsules' lowest lines span x -0.05 ... 0.13,
# y +-0.027, z -0.035 below the frame)
SOLE = np.array(
    [[-0.05, -0.02, -0.035], [0.12, -0.025, -0.035], [0.12, 0.025, -0.035], [-0.05, 0.02, -0.035]]
)
DEFAULT = {"hip_pitch": -0.312, "knee": 0.669, "ankle_pitch": -0.363, "elbow": 0.6, "shoulder_pitch": 0.2}
GAINS = WbcGains(frames=(FrameTask("torso_link", ori=5.0), FrameTask("pelvis", ori=2.0)))


def _g1_xml() -> Path:
    spec = importlib.util.find_spec("mjlab")  # installed by the Makefile (asset source, --no-deps)
    assert spec is not None and spec.submodule_search_locations, "mjlab is not installed: run `make venv`"
    return Path(
        list(spec.submodule_search_locations)[0], "asset_zoo", "robots", "unitree_g1", "xmls", "g1.xml"
    )


def _model(floor: bool, timestep: float = 0.002) -> mujoco.MjModel:
    spec = mujoco.MjSpec.from_file(str(_g1_xml()))
    spec.option.timestep = timestep
    for joint in spec.joints:  # rotor inertia (the G1's are 0.003-0.03 kg m^2): explicit torques stay stable
        if joint.type == mujoco.mjtJoint.mjJNT_HINGE:
            joint.armature = 0.01
    for geom in spec.geoms:  # the simulator's contacts: robot against floor only, feet with friction
        if geom.contype or geom.conaffinity:
            geom.contype, geom.conaffinity = 0, 1
            geom.condim = 3 if "foot" in geom.name else 1
            geom.friction[0] = 0.6
    if floor:
        spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 0.05])
    return spec.compile()


def _standing(model: mujoco.MjModel) -> np.ndarray:
    """Default knees-bent pose with the soles on z = 0."""
    q = np.zeros(model.nq)
    q[3] = 1.0
    for j in range(1, model.njnt):
        name = model.joint(j).name.removesuffix("_joint")
        stem = name.removeprefix("left_").removeprefix("right_")
        q[model.jnt_qposadr[j]] = DEFAULT.get(stem, 0.0)
    d = mujoco.MjData(model)
    d.qpos[:] = q
    mujoco.mj_kinematics(model, d)
    foot = model.body(FEET[0]).id
    q[2] = -(d.xpos[foot] + d.xmat[foot].reshape(3, 3) @ SOLE[0])[2]
    return q


def _controller(model: mujoco.MjModel, q: np.ndarray, frames: int = 10) -> WholeBodyQP:
    joints = tuple(model.joint(j).name for j in range(1, model.njnt))
    zeros = np.zeros((frames, model.nv))
    ref = motion_reference(
        model, np.tile(q, (frames, 1)), zeros, zeros, (*FEET, "torso_link", "pelvis"), 0.02
    )
    effort = model.jnt_actfrcrange[1:, 1].copy()
    effort[effort == 0] = 100.0
    return WholeBodyQP(model, joints, effort, {f: SOLE for f in FEET}, ref, mu=0.6, gains=GAINS)


def test_static_torques_equal_pinocchio_rnea() -> None:
    """Static pose (v = 0, reference at rest): the QP's torques are tau = rnea(q, 0, qdd)_joints -
    (sum_c J_c^T f_c)_joints with Pinocchio's RNEA and contact Jacobians (qdd ~ 0), and the contact
    wrench is the static one: sum f = (0, 0, m g), centre of pressure under the COM."""
    import pinocchio as pin  # a project dependency (pyproject: pin)

    model = _model(floor=False)
    q = _standing(model)
    q[7 + 15] = 0.3  # waist yaw: an asymmetric pose (still identity base orientation)
    wbc = _controller(model, q)
    sol = wbc.solve(q, np.zeros(model.nv), 0, np.array([True, True]))
    assert sol.status == "solved"
    assert np.abs(sol.qacc).max() < 1e-3
    pm = pin.buildModelFromMJCF(str(_g1_xml()))
    pd = pm.createData()
    qp = np.concatenate([q[:3], q[4:7], q[3:4], q[7:]])  # Pinocchio's quaternion is x y z w
    # identity base orientation: Pinocchio's local base velocity coordinates equal MuJoCo's
    tau = pin.rnea(pm, pd, qp, np.zeros(pm.nv), sol.qacc)
    pin.forwardKinematics(pm, pd, qp)
    pin.updateFramePlacements(pm, pd)
    pin.computeJointJacobians(pm, pd, qp)
    total, moment = np.zeros(3), np.zeros(3)
    for foot in FEET:
        frame = pm.frames[pm.getFrameId(foot)]
        jac = pin.getJointJacobian(pm, pd, frame.parentJoint, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        origin = pd.oMi[frame.parentJoint].translation
        for p, f in zip(SOLE, sol.forces[foot]):
            world = pd.oMi[frame.parentJoint].act(frame.placement.act(p))
            r = world - origin
            skew = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
            tau -= (jac[:3] - skew @ jac[3:]).T @ f  # point Jacobian v + w x r
            total += f
            moment += np.cross(world, f)
    np.testing.assert_allclose(sol.tau, tau[6:], atol=0.05)  # N m; OSQP tolerance 1e-5 x m g
    mass = sum(i.mass for i in pm.inertias)
    np.testing.assert_allclose(total, [0, 0, mass * G], atol=0.1)
    com = pin.centerOfMass(pm, pd, qp)
    cop = np.array([-moment[1], moment[0]]) / total[2]
    np.testing.assert_allclose(cop, com[:2], atol=1e-3)


def test_push_inside_capture_point_bound_is_recovered() -> None:
    """Linear inverted pendulum: omega = sqrt(g / z_com), capture point xi = x + v / omega. A pelvis
    velocity impulse dv (every body's velocity changes by dv, so the COM's does) that leaves xi inside
    the support polygon is recovered without a step: here xi at 60 % of the way from the COM to the
    soles' front edge, dv = 0.6 (x_front - x) omega. Torque control (the QP's torques applied every
    5 ms step)."""
    model = _model(floor=True, timestep=0.005)
    q = _standing(model)
    wbc = _controller(model, q)
    data = mujoco.MjData(model)
    data.qpos[:] = q
    mujoco.mj_forward(model, data)
    feet0 = np.array([data.xpos[model.body(f).id] for f in FEET])
    front = max(
        (data.xpos[b] + data.xmat[b].reshape(3, 3) @ SOLE[1])[0] for b in (model.body(f).id for f in FEET)
    )
    x, z = data.subtree_com[1][0], data.subtree_com[1][2]
    omega = np.sqrt(G / z)
    dv = 0.6 * (front - x) * omega
    assert 0.1 < dv < 0.5
    mujoco.mj_forward(model, data)
    stance = np.array([True, True])
    peak = x
    for k in range(400):
        if k == 20:
            data.qvel[0] += dv
        sol = wbc.solve(data.qpos.copy(), data.qvel.copy(), 0, stance)
        data.qfrc_applied[:] = 0
        data.qfrc_applied[wbc.dofs] = sol.tau
        mujoco.mj_step(model, data)
        peak = max(peak, data.subtree_com[1][0])
    feet = np.array([data.xpos[model.body(f).id] for f in FEET])
    assert np.abs(feet - feet0).max() < 0.01  # no step
    assert abs(data.qpos[2] - q[2]) < 0.02
    assert np.linalg.norm(data.qvel[:3]) < 0.05
    assert peak < front  # the COM never left the support
    assert abs(data.subtree_com[1][0] - x) < 0.02


def test_servo_targets_reproduce_torque() -> None:
    """target = q_m + (tau + kd v_m) / kp: the servo torque kp (target - q) - kd v equals tau at the
    mean state (period 0: at the current state)."""
    rng = np.random.default_rng(0)
    tau, q, v, a = rng.normal(size=(4, 5))
    kp, kd = rng.uniform(20, 100, 5), rng.uniform(1, 5, 5)
    t = servo_targets(tau, q, v, a, kp, kd, 0.0)
    np.testing.assert_allclose(kp * (t - q) - kd * v, tau)
    period = 0.02
    t = servo_targets(tau, q, v, a, kp, kd, period)
    s = np.linspace(0, period, 2001)[:, None]
    mean = np.mean(kp * (t - (q + v * s + a * s**2 / 2)) - kd * (v + a * s), axis=0)
    np.testing.assert_allclose(mean, tau, atol=1e-5)  # quadrature error
