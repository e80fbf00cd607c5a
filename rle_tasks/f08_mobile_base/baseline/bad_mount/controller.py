"""Reference controller of family 08: drive to the shelf, then IK + PD with gravity compensation.

It rebuilds its own model (this directory's robot.xml with the verifier's public wheel model, the
arm and the payload), parks the base so that its front stops 5 cm before the shelf, solves IK
(Pinocchio + OSQP, rle_design.kinematics.ik) for a pre-grasp point 15 cm in front of the target and for
the target with the tool axis horizontal, and tracks a joint-space path with a critically damped PD
plus the model's gravity and Coriolis torques. Wheels follow a proportional position controller.
"""

import mujoco
import numpy as np

from rle_design.mjcf import load_design
from rle_tasks.f08_mobile_base.poses import PARK_GAP, _ik
from rle_tasks.f08_mobile_base.scene import build_scene
from rle_tasks.f08_mobile_base.wheels import WHEELS, mecanum_speeds

SHELF_FRONT_X = 1.10
V_MAX, A_MAX, K_POS = 0.5, 0.8, 2.0
T_DRIVE, T_ENTER = 2.6, 1.2
OMEGA = 12.0  # PD natural frequency [rad/s] (50 Hz zero-order hold)

_S = {}


def reset(arm, target, payload_kg, layout):
    key = (arm, int(round(payload_kg)))
    if key not in _S:
        design = load_design(".")
        _S[key] = build_scene(design.fresh_spec, arm, int(round(payload_kg)))
    sc = _S[key]
    target = np.asarray(target, dtype=float)
    x_park = SHELF_FRONT_X - PARK_GAP - sc.front_extent()
    d = sc.rest_data(x_park)
    pre = _ik(sc, d, target - np.array([0.22, 0.0, 0.0]), np.array([1.0, 0.0, 0.0])).q
    goal = _ik(sc, d, target, np.array([1.0, 0.0, 0.0])).q
    ids = [mujoco.mj_name2id(sc.model, mujoco.mjtObj.mjOBJ_BODY, w) for w in WHEELS]
    wheel_xy = np.array([d.xpos[i][:2] for i in ids]) - d.xpos[sc.chassis][:2]
    _S["cur"] = dict(
        sc=sc,
        data=mujoco.MjData(sc.model),
        x_park=x_park,
        pre=pre,
        goal=goal,
        layout=layout,
        wheel_xy=wheel_xy,
        q0=None,
        v=0.0,
    )


def _arm_path(s, t, q_now):
    if s["q0"] is None:
        s["q0"] = q_now.copy()
    if t < T_DRIVE:
        a = min(1.0, t / T_DRIVE)
        a = a * a * (3 - 2 * a)
        return s["q0"] + a * (s["pre"] - s["q0"])
    a = min(1.0, (t - T_DRIVE) / T_ENTER)
    a = a * a * (3 - 2 * a)
    return s["pre"] + a * (s["goal"] - s["pre"])


def control(t, qpos, qvel, ctrl):
    s = _S["cur"]
    sc, d, lay = s["sc"], s["data"], s["layout"]
    d.qpos[:] = qpos
    d.qvel[:] = qvel
    mujoco.mj_forward(sc.model, d)
    out = np.zeros(sc.model.nu)
    # base: P control on x with speed and acceleration limits, heading and y held
    x, y = qpos[0], qpos[1]
    yaw = 2.0 * np.arctan2(qpos[6], qpos[3])
    v_des = float(np.clip(K_POS * (s["x_park"] - x), -V_MAX, V_MAX))
    s["v"] = float(np.clip(v_des, s["v"] - A_MAX / 50.0, s["v"] + A_MAX / 50.0))
    out[lay["wheel_actuators"]] = mecanum_speeds(s["v"], -2.0 * y, -2.0 * yaw, s["wheel_xy"])
    # arm: gravity/Coriolis compensation + critically damped PD toward the path
    aq, av = lay["arm_qpos"], lay["arm_qvel"]
    q_des = _arm_path(s, t, qpos[aq])
    m = sc.model
    inertia = d.M[m.M_rowadr[av] + m.M_rownnz[av] - 1]
    tau = d.qfrc_bias[av] + inertia * OMEGA**2 * (q_des - qpos[aq]) - 2.0 * inertia * OMEGA * qvel[av]
    out[lay["arm_actuators"]] = tau
    return out
