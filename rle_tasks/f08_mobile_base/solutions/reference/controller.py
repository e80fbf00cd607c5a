"""Reference controller of family 08: drive to the shelf, then IK + PD with gravity compensation.

Self-contained (numpy, mujoco, pinocchio and the rle_design toolkit only). It builds its own model:
this directory's robot.xml with the arm and payload attached at ``arm_mount_site`` and the shelf of
the catalog (no wheel joints: base and arm states are copied through the ``layout`` indices). Per
target it picks an approach pitch whose straight entry path (IK waypoints from 22 cm in front of the
target, Pinocchio + OSQP via rle_design.kinematics.ik) keeps 1.5 cm of clearance to the shelf, then:
0-1 s arm from stowed to the pre-entry pose while the base is far from the shelf; 1-~2.8 s base
driven to the park position (front 5 cm before the shelf) by a P controller with mecanum wheel
speeds; 2.8-4 s straight entry; then hold. Arm torque: the model's gravity/Coriolis torque plus a
critically damped PD scaled by each joint's effective inertia (stable under the 50 Hz hold) plus
dry-friction compensation, with a damped least-squares correction for the base's actual pose.
"""

import mujoco
import numpy as np
import pinocchio as pin

from rle_design.catalog import load_catalog
from rle_design.kinematics.ik import chain_from_mujoco, solve_ik
from rle_design.mjcf import load_design
from rle_design.scene import compose, drop_visual_meshes

V_MAX, A_MAX, K_POS = 0.5, 0.8, 3.0
T_ARM, T_ENTRY, T_ENTER = 1.0, 2.8, 1.2  # nominal phase times [s]; T_ARM grows with the arm motion
ARM_SPEED = 1.2  # largest joint speed of the stowed -> pre-entry move [rad/s] (gentle on the base)
OMEGA = 12.0  # closed-loop natural frequency [rad/s] (omega dt = 0.24 at 50 Hz)
ENTRY, N_WAY, CLEARANCE, PARK_GAP = 0.22, 6, 0.03, 0.05
PITCHES = (0.0, 0.3, 0.6, -0.2, 0.9, -0.4)  # approach axis pitch candidates (down positive) [rad]
WHEEL_R = 0.0762
ROLLER = {"wheel_fl": (1, -1), "wheel_fr": (1, 1), "wheel_rl": (1, 1), "wheel_rr": (1, -1)}  # roller axis s
STOWED = {
    "panda": (0.0, np.pi / 16.0, 0.0, -np.pi / 2.0 - np.pi / 3.0, 0.0, np.pi - 0.2, np.pi / 4),
    "ur5e": (-0.470, -1.735, 2.480, -2.275, -1.590, -1.991),
    "xarm7": (0.0, 0.0, 0.0, 0.39 * np.pi, 0.0, 0.39 * np.pi, 0.0),
}


def mecanum_speeds(vx, vy, wz, wheel_xy):
    """Wheel speeds [rad/s] for a chassis twist: omega_i = sqrt2 (v_i . s_i) / r (instruction.md)."""
    out = []
    for s, (px, py) in zip(ROLLER.values(), wheel_xy):
        s = np.array(s, dtype=float) / np.sqrt(2.0)
        out.append(np.sqrt(2.0) * float(np.array([vx - wz * py, vy + wz * px]) @ s) / WHEEL_R)
    return np.array(out)


class _Model:
    """Own model: base + arm + payload + shelf, without wheel joints."""

    def __init__(self, arm, payload_kg):
        spec = load_design(".").fresh_spec()
        compose(spec, arm, {1: "payload_1kg", 2: "payload_2kg"}.get(payload_kg), mount_site="arm_mount_site")
        drop_visual_meshes(spec, f"{arm}/")  # physics and planning only: no visual meshes to compile
        shelf = load_catalog("shelf").extra
        x0, w, dep, t = shelf["front_x"], shelf["width"], shelf["depth"], shelf["board_thickness"]
        top = max(shelf["level_heights"]) + 0.30
        body = spec.worldbody.add_body(name="shelf", pos=[x0 + dep / 2, 0, 0])
        box = mujoco.mjtGeom.mjGEOM_BOX
        for i, z in enumerate(shelf["level_heights"]):
            body.add_geom(
                name=f"shelf_board_{i}", type=box, size=[dep / 2, w / 2, t / 2], pos=[0, 0, z - t / 2]
            )
        for side in (-1, 1):
            body.add_geom(
                name=f"shelf_side_{side}",
                type=box,
                size=[dep / 2, t / 2, top / 2],
                pos=[0, side * (w / 2 + t / 2), top / 2],
            )
        body.add_geom(
            name="shelf_back", type=box, size=[t / 2, w / 2 + t, top / 2], pos=[dep / 2 + t / 2, 0, top / 2]
        )
        spec.compiler.usethread = False
        m = self.model = spec.compile()
        self.data = mujoco.MjData(m)
        joints = [m.joint(j).name for j in range(m.njnt) if m.joint(j).name.startswith(f"{arm}/")]
        self.chain = chain_from_mujoco(m, joints, f"{arm}/tool_site")
        self.shelf = {g for g in range(m.ngeom) if m.geom(g).name.startswith("shelf_")}
        m.geom_margin[list(self.shelf)] = CLEARANCE
        chassis = m.body("chassis").id
        self.robot = {g for g in range(m.ngeom) if self._under(m, int(m.geom_bodyid[g]), chassis)}
        arm_geoms = {
            g for g in self.robot if m.body(m.geom_bodyid[g]).name.startswith((f"{arm}/", "payload/"))
        }
        d = self.rest(0.0, STOWED[arm])
        mujoco.mj_kinematics(m, d)
        self.front = max(self._aabb_max_x(d, g) for g in self.robot - arm_geoms)
        self.wheel_xy = np.array([d.xpos[m.body(w).id][:2] for w in ROLLER])
        self.arm = arm

    @staticmethod
    def _under(m, b, root):
        while b > 0:
            if b == root:
                return True
            b = int(m.body_parentid[b])
        return False

    def _aabb_max_x(self, d, g):
        c, h = self.model.geom_aabb[g][:3], self.model.geom_aabb[g][3:]
        corners = c + h * np.array([[a, b, e] for a in (-1, 1) for b in (-1, 1) for e in (-1, 1)])
        return float((d.geom_xpos[g] + corners @ d.geom_xmat[g].reshape(3, 3).T)[:, 0].max())

    def rest(self, x, q_arm):
        m, d = self.model, self.data
        d.qpos[:] = m.qpos0
        d.qpos[0] = x
        d.qpos[1] = 0.0
        d.qpos[2] = WHEEL_R
        d.qpos[3:7] = [1, 0, 0, 0]
        d.qpos[self.chain.qpos_adr] = q_arm
        mujoco.mj_kinematics(m, d)
        return d


def _ik(mdl, d, target_world, axis_world):
    ch = mdl.chain
    tgt = ch.to_base(d, target_world)
    _, rot = ch.base_pose(d)
    axis = rot.T @ axis_world
    stowed = np.array(STOWED[mdl.arm])
    seeds = [solve_ik(ch, tgt, stowed, max_iter=40, tol=5e-3).q, stowed]
    rng = np.random.default_rng(7)
    lo, hi = np.maximum(ch.lower, -np.pi), np.minimum(ch.upper, np.pi)
    seeds += [rng.uniform(lo, hi) for _ in range(3)]
    best = None
    for q0 in seeds:
        r = solve_ik(ch, tgt, q0, axis=axis, max_iter=80)
        if best is None or (r.position_error, r.axis_error) < (best.position_error, best.axis_error):
            best = r
        if best.converged:
            break
    return best


_S = {}


def _collides(mdl, d, q):
    d.qpos[mdl.chain.qpos_adr] = q
    mujoco.mj_kinematics(mdl.model, d)
    mujoco.mj_collision(mdl.model, d)
    rob, sh = mdl.robot, mdl.shelf
    return any(
        (c.geom1 in rob and c.geom2 in sh) or (c.geom2 in rob and c.geom1 in sh) for c in d.contact[: d.ncon]
    )


def _plan(mdl, x_park, target):
    best = None
    for pitch in PITCHES:
        d = mdl.rest(x_park, STOWED[mdl.arm])
        _, rot = mdl.chain.base_pose(d)
        axis = np.array([np.cos(pitch), 0.0, -np.sin(pitch)])
        r = _ik(mdl, d, target - ENTRY * axis, axis)
        path, err = [r.q], r.position_error
        if err > 0.05 and best is not None:
            continue  # this approach is out of reach
        for a in np.linspace(0.0, 1.0, N_WAY + 1)[1:]:
            p = target - (1.0 - a) * ENTRY * axis
            r = solve_ik(
                mdl.chain, mdl.chain.to_base(d, p), path[-1], axis=rot.T @ axis, max_iter=80, posture=1e-2
            )
            path.append(r.q)
            err = max(err, r.position_error)
        dense = [path[i] + f * (path[i + 1] - path[i]) for i in range(N_WAY) for f in (0.0, 0.5)] + [path[-1]]
        hits = sum(_collides(mdl, d, q) for q in dense)
        cost = (hits, err > 0.01, err)
        if best is None or cost < best[0]:
            best = (cost, axis, np.array(path))
        if hits == 0 and err < 0.01:
            break
    return best[1], best[2]


def reset(arm, target, payload_kg, layout):
    key = (arm, int(round(payload_kg)))
    if key not in _S:
        _S[key] = _Model(arm, int(round(payload_kg)))
    mdl = _S[key]
    target = np.asarray(target, dtype=float)
    x_park = load_catalog("shelf").extra["front_x"] - PARK_GAP - mdl.front
    axis, path = _plan(mdl, x_park, target)
    _S["cur"] = dict(
        mdl=mdl,
        x_park=x_park,
        path=path,
        target=target,
        axis=axis,
        pd=mdl.chain.model.createData(),
        layout=layout,
        q0=None,
        v=0.0,
        t_arm=None,
        t_entry=None,
    )


def _smooth(a):
    a = min(1.0, max(0.0, a))
    return a * a * (3 - 2 * a)


def _arm_target(s, t, q_now):
    if s["q0"] is None:
        s["q0"] = q_now.copy()
    path = s["path"]
    if s["t_arm"] is None:
        s["t_arm"] = float(np.clip(1.5 * np.abs(path[0] - s["q0"]).max() / ARM_SPEED, T_ARM, 2.4))
        s["t_entry"] = s["t_arm"] + (T_ENTRY - T_ARM)
    if t < s["t_arm"]:
        return s["q0"] + _smooth(t / s["t_arm"]) * (path[0] - s["q0"])
    a = _smooth((t - s["t_entry"]) / T_ENTER)
    x = a * (len(path) - 1)
    i = min(int(x), len(path) - 2)
    q_ref = path[i] + (x - i) * (path[i + 1] - path[i])
    if t < s["t_entry"] - 0.5:
        return q_ref
    # correct for the base's actual pose: damped least-squares steps toward the world point
    ch = s["mdl"].chain
    p_base = ch.to_base(s["mdl"].data, s["target"] - (1.0 - a) * ENTRY * s["axis"])
    q = q_ref.copy()
    for _ in range(2):
        pin.framesForwardKinematics(ch.model, s["pd"], q)
        pin.computeJointJacobians(ch.model, s["pd"], q)
        jac = pin.getFrameJacobian(ch.model, s["pd"], ch.tool_frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)[
            :3
        ]
        e = p_base - s["pd"].oMf[ch.tool_frame].translation
        q = np.clip(q + jac.T @ np.linalg.solve(jac @ jac.T + 1e-3 * np.eye(3), e), ch.lower, ch.upper)
    return q


def control(t, qpos, qvel, ctrl):
    s = _S["cur"]
    mdl, lay = s["mdl"], s["layout"]
    m, d, ch = mdl.model, mdl.data, mdl.chain
    aq, av = lay["arm_qpos"], lay["arm_qvel"]
    d.qpos[:7] = qpos[lay["chassis_qpos"]]
    d.qvel[:6] = qvel[lay["chassis_qvel"]]
    d.qpos[ch.qpos_adr] = qpos[aq]
    d.qvel[ch.dof_adr] = qvel[av]
    mujoco.mj_forward(m, d)
    out = np.zeros(len(lay["actuators"]))
    # base: waits for the arm, then P control on x with speed/acceleration limits; y and heading held
    x, y = qpos[lay["chassis_qpos"][0]], qpos[lay["chassis_qpos"][1]]
    qw, qz = qpos[lay["chassis_qpos"][3]], qpos[lay["chassis_qpos"][6]]
    yaw = 2.0 * np.arctan2(qz, qw)
    v_des = float(np.clip(K_POS * (s["x_park"] - x), -V_MAX, V_MAX)) if t >= (s["t_arm"] or T_ARM) else 0.0
    s["v"] = float(np.clip(v_des, s["v"] - A_MAX / 50.0, s["v"] + A_MAX / 50.0))
    out[lay["wheel_actuators"]] = mecanum_speeds(s["v"], -4.0 * y, -4.0 * yaw, mdl.wheel_xy)
    # arm
    q_des = _arm_target(s, t, qpos[aq])
    dofs = ch.dof_adr
    full = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, full)
    m_arm = full[np.ix_(dofs, dofs)]
    e = q_des - qpos[aq]
    # computed torque: decoupled critically damped joints at OMEGA, gravity/Coriolis compensated
    tau = d.qfrc_bias[dofs] + m_arm @ (OMEGA**2 * e - 2.0 * OMEGA * qvel[av])
    tau = tau + m.dof_frictionloss[dofs] * np.tanh(e / 0.02)
    out[lay["arm_actuators"]] = tau
    return out
