"""Scripted, state-based experts of the stand-in's tasks (demonstrations and tests).

An expert reads the objects' initial poses (``StandinEnv.privileged``, which no served policy
sees), plans each arm's tool-site path as straight-line segments between grasp waypoints, and turns
every 10 Hz control step's tool pose into joint targets by damped least-squares inverse kinematics
warm-started from the previous step. The grippers point down; their yaw turns the fingers across
the part they grasp. Its actions are exactly what a served policy would send (14-D).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.scene.robots import robot_constants
from rle_tasks.envs.standin import tasks as T
from rle_tasks.envs.standin.env import ACTION_DIM, HOME, StandinEnv
from rle_tasks.envs.standin.scene import ARMS

__all__ = ["Expert", "run_expert"]

IK_ITERS = 30
IK_DAMPING = 1e-3
OPEN, CLOSED = 1.0, 0.0


@dataclass
class _Seg:
    steps: int
    pos: object  # a position [m], None (hold the last pose) or a function of the objects' poses
    yaw: float | None
    grip: float


def _tool_down(yaw: float) -> np.ndarray:
    """Rotation matrix of a tool pointing down (z = -world z), turned by ``yaw`` about world z."""
    c, s = np.cos(yaw), np.sin(yaw)
    rz = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return rz @ np.diag([1.0, -1.0, -1.0])


class _Ik:
    def __init__(self, env: StandinEnv) -> None:
        self.m = env.model
        self.d = mujoco.MjData(self.m)
        self.site = {p: self.m.site(p + "hand/grip_site").id for p in ARMS}
        self.qadr = {p: env._q[6 * i : 6 * i + 6] for i, p in enumerate(ARMS)}
        self.dadr = {
            p: np.array([self.m.jnt_dofadr[self.m.joint(p + j).id] for j in robot_constants("ur5e").joints])
            for p in ARMS
        }
        self.lo, self.hi = env._lo[:6], env._hi[:6]

    def solve(self, arm: str, q0: np.ndarray, pos: np.ndarray, rot: np.ndarray) -> np.ndarray:
        m, d = self.m, self.d
        q = q0.copy()
        jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
        for _ in range(IK_ITERS):
            d.qpos[self.qadr[arm]] = q
            mujoco.mj_kinematics(m, d)
            mujoco.mj_comPos(m, d)
            sid = self.site[arm]
            ep = pos - d.site_xpos[sid]
            cur = d.site_xmat[sid].reshape(3, 3)
            er = 0.5 * sum(np.cross(cur[:, k], rot[:, k]) for k in range(3))
            err = np.concatenate([ep, er])
            if np.linalg.norm(err) < 1e-5:
                break
            mujoco.mj_jacSite(m, d, jp, jr, sid)
            j = np.vstack([jp, jr])[:, self.dadr[arm]]
            q = q + j.T @ np.linalg.solve(j @ j.T + IK_DAMPING * np.eye(6), err)
            q = np.clip(q, self.lo, self.hi)
        return q

    def pose(self, arm: str, q: np.ndarray) -> np.ndarray:
        self.d.qpos[self.qadr[arm]] = q
        mujoco.mj_kinematics(self.m, self.d)
        return self.d.site_xpos[self.site[arm]].copy()


def _grasp_yaw(obj_yaw: float, base: float) -> float:
    """Gripper yaw closing across a part whose own yaw is ``obj_yaw`` (fingers close along the
    gripper's y axis; ``base`` is the yaw that closes across the part at zero yaw), folded into
    (-pi/2, pi/2] so the wrist turns as little as possible."""
    y = base + obj_yaw
    return float((y + np.pi / 2) % np.pi - np.pi / 2)


def _plans(env: StandinEnv) -> dict[str, list[_Seg]]:
    top = T.TOP_Z + env.look.table_dz
    obj = env.privileged()
    name = env.task.name
    up = np.array([0.0, 0.0, 1.0])

    def yaw_of(q: np.ndarray) -> float:
        w, z = q[3], q[6]
        return float(2 * np.arctan2(z, w))

    if name == "lift_pot":
        p = obj["pot"]
        yaw = yaw_of(p)
        c, s = np.cos(yaw), np.sin(yaw)
        hz = top + 0.005 + 2 * T.POT_WALL[1] - T.HANDLE[2]
        out = {}
        for arm, sy in zip(ARMS, (1, -1), strict=True):
            off = sy * (T.POT_HALF[1] + T.HANDLE[1] + 0.005)
            h = np.array([p[0] - s * off, p[1] + c * off, hz])
            gy = _grasp_yaw(yaw, 0.0)
            out[arm] = [
                _Seg(22, h + 0.10 * up, gy, OPEN),
                _Seg(12, h, gy, OPEN),
                _Seg(6, None, gy, CLOSED),
                _Seg(20, h + 0.16 * up, gy, CLOSED),
                _Seg(8, None, gy, CLOSED),
            ]
        return out
    if name == "handover_bar":
        p = obj["bar"]
        yaw = yaw_of(p)
        u = np.array([-np.sin(yaw), np.cos(yaw), 0.0])
        gy = _grasp_yaw(yaw, 0.0)
        g_left = p[:3] + 0.05 * u
        lift_z = top + 0.22
        centre = np.array([0.12, 0.04, lift_z])
        left_hold = centre + 0.05 * u

        def right_grasp(o: dict[str, np.ndarray], above: float) -> np.ndarray:
            """The bar's point 5 cm from its centre towards the right arm, where the bar is now."""
            b = o["bar"]
            axis = np.empty(3)
            mujoco.mju_rotVecQuat(axis, np.array([0.0, 1.0, 0.0]), b[3:])
            return b[:3] - 0.05 * axis + above * up

        final = np.array([0.12, -0.20, lift_z])
        left = [
            _Seg(22, g_left + 0.10 * up, gy, OPEN),
            _Seg(12, g_left, gy, OPEN),
            _Seg(6, None, gy, CLOSED),
            _Seg(14, g_left + 0.12 * up, gy, CLOSED),
            _Seg(20, left_hold, gy, CLOSED),
            _Seg(40, None, gy, CLOSED),  # the right arm comes and grasps
            _Seg(6, None, gy, OPEN),
            _Seg(12, left_hold + 0.10 * up, gy, OPEN),
            _Seg(30, None, gy, OPEN),
        ]
        home = None
        right = [
            _Seg(74, home, None, OPEN),
            _Seg(22, lambda o: right_grasp(o, 0.10), gy, OPEN),
            _Seg(12, lambda o: right_grasp(o, 0.0), gy, OPEN),
            _Seg(6, None, gy, CLOSED),
            _Seg(18, None, gy, CLOSED),  # the left arm lets go and leaves
            _Seg(22, final - 0.05 * u, gy, CLOSED),
            _Seg(8, None, gy, CLOSED),
        ]
        return {"left/": left, "right/": right}
    tray = obj["tray"]
    plans = {}
    waits = {"left/": (0, 50), "right/": (50, 0)}
    for arm, block, dy in (("left/", "red", 0.05), ("right/", "blue", -0.05)):
        b = obj[block]
        gy = _grasp_yaw(yaw_of(b), 0.0)
        g = b[:3].copy()
        drop = np.array([tray[0], tray[1] + dy, top + 0.10])
        before, after = waits[arm]
        segs = [
            _Seg(22, g + 0.10 * up, gy, OPEN),
            _Seg(12, g, gy, OPEN),
            _Seg(6, None, gy, CLOSED),
            _Seg(14, g + 0.16 * up, gy, CLOSED),
        ]
        if before:
            segs.append(_Seg(before, None, gy, CLOSED))
        segs += [
            _Seg(20, drop + 0.06 * up, gy, CLOSED),
            _Seg(10, drop, gy, CLOSED),
            _Seg(5, None, gy, OPEN),
            _Seg(10, drop + 0.10 * up, gy, OPEN),
            _Seg(5, drop + np.array([-0.15, 1.5 * dy, 0.12]), gy, OPEN),
        ]
        if after:
            segs.append(_Seg(after, None, gy, OPEN))
        plans[arm] = segs
    return plans


class Expert:
    """The expert of the episode ``env`` was just reset to: ``act()`` gives the next 14-D action,
    planning each segment when it starts (from the objects' poses then), until ``done``."""

    def __init__(self, env: StandinEnv) -> None:
        self.env = env
        self.ik = _Ik(env)
        self.plans = _plans(env)
        self.k = {a: 0 for a in ARMS}  # segment index
        self.t = {a: 0 for a in ARMS}  # step in the segment
        self.q = {a: HOME.copy() for a in ARMS}
        self.pos = {a: self.ik.pose(a, HOME) for a in ARMS}
        self.rot = {a: _tool_down(0.0) for a in ARMS}
        self.seg: dict[str, tuple] = {}
        self.grip = {a: OPEN for a in ARMS}

    @property
    def done(self) -> bool:
        return all(self.k[a] >= len(self.plans[a]) for a in ARMS)

    def _arm(self, arm: str) -> np.ndarray:
        plan = self.plans[arm]
        if self.k[arm] < len(plan):
            seg = plan[self.k[arm]]
            if self.t[arm] == 0:
                goal = seg.pos(self.env.privileged()) if callable(seg.pos) else seg.pos
                start = self.pos[arm].copy()
                goal = start if goal is None else np.asarray(goal, float)
                rot = self.rot[arm] if seg.yaw is None else _tool_down(seg.yaw)
                self.seg[arm] = (start, goal, rot, seg.pos is not None or seg.yaw is not None)
            start, goal, rot, moves = self.seg[arm]
            self.t[arm] += 1
            a = 0.5 - 0.5 * np.cos(np.pi * self.t[arm] / seg.steps)  # smooth start and stop
            if moves:
                self.q[arm] = self.ik.solve(arm, self.q[arm], start + (goal - start) * a, rot)
            self.grip[arm] = seg.grip
            if self.t[arm] == seg.steps:
                self.pos[arm], self.rot[arm] = goal, rot
                self.k[arm] += 1
                self.t[arm] = 0
        return np.concatenate([self.q[arm], [self.grip[arm]]])

    def act(self) -> np.ndarray:
        out = np.concatenate([self._arm(a) for a in ARMS])
        assert out.shape == (ACTION_DIM,)
        return out


def run_expert(env: StandinEnv, seed: int, views: bool = False) -> tuple[bool, dict[str, np.ndarray]]:
    """Reset to ``seed`` and execute the expert to its end; (success at any step, recording:
    ``state`` (T, 16), ``action`` (T, 14) and with ``views`` ``head``/``front`` (T, 128, 128, 3))."""
    obs = env.reset(seed)
    expert = Expert(env)
    rec: dict[str, list] = {"state": [], "action": []}
    if views:
        rec |= {"head": [], "front": []}
    ok = False
    while not expert.done:
        a = expert.act()
        rec["state"].append(obs["state"])
        if views:
            rec["head"].append(obs["head"])
            rec["front"].append(obs["front"])
        rec["action"].append(a)
        ok = env.step(a) or ok
        obs = env.observe(views=views)
    return ok, {k: np.asarray(v) for k, v in rec.items()}
