"""The whole-body QP expert of one clip (``Expert``): privileged state in, servo targets out.

The expert reads the simulator's true ``qpos``/``qvel`` and the clip's contact schedule, runs the
whole-body QP (``rle_design.control.wbc``) on the nominal model (never the perturbed one) once per
policy step and turns its torques into servo targets; on top of the clip it may emphasise balance when
the capture point strays (``balance``) and take capture steps the clip does not have (``stepping``,
``expert_params.StepParams``). Its rollouts and command line are in ``expert``.
"""

from __future__ import annotations

import math
import time

import mujoco
import numpy as np

from rle_design.control.wbc import WholeBodyQP, servo_targets
from rle_design.control.wbc_reference import motion_reference
from rle_design.control.wbc_tasks import WbcGains

from ..public.clip import Clip, clip_qpos
from ..public.env import POLICY_DT, TrackingEnv
from ..public.g1 import FOOT_FRICTION, g1_model
from ..public.g1_constants import G1
from ..public.inverse_dynamics import finite_differences
from ..public.soles import sole_polygon
from .expert_params import DEFAULT_GAINS, STEPPING, StepParams

__all__ = ["Expert"]


def _outside(points: np.ndarray, x: np.ndarray) -> float:
    """Signed distance of ``x`` outside the convex hull of ``points`` (xy) [m] (negative inside)."""
    from scipy.spatial import ConvexHull

    hull = ConvexHull(points)
    # equations: n . p + c <= 0 inside, unit normals
    return float(np.max(hull.equations[:, :2] @ x + hull.equations[:, 2]))


class Expert:
    """The QP tracker of one clip on the nominal G1.

    Args:
        clip: The reference.
        gains: QP task weights and gains.
        schedule: (F, 2) contact flags of the feet (default: the clip's stance flags).
        period: Hold time of each servo target [s] (``POLICY_DT`` at 50 Hz).
        sole_scale: The contact polygon is the sole's shrunk by this factor about its centroid [1].
        stepping: Capture steps the clip does not have (``_capture_step``); None: off.
        servo_joints: Joints whose targets are the reference plus the QP's torque over kp (the servo's own
            PD, free of latency, does their feedback): the wrists oscillate under two steps of latency
            without joint friction otherwise (dance seed 202, friction removed: J 0.35 -> 0.038). Off:
            on seeds 200-215 the score did not improve.
        balance: ``(e0, e1, boost, floor)`` of the capture-point emphasis (``_balance_scales``); None: off.
        smoothing: Low-pass of the targets, ``target = s target_prev + (1 - s) target_qp`` [1].
    """

    def __init__(
        self,
        clip: Clip,
        gains: WbcGains = DEFAULT_GAINS,
        schedule: np.ndarray | None = None,
        period: float = POLICY_DT,
        smoothing: float = 0.0,
        sole_scale: float = 1.0,
        balance: tuple[float, float, float, float] | None = None,
        stepping: StepParams | None = STEPPING,
        settings: dict | None = None,
        servo_joints: tuple[str, ...] = (),
    ) -> None:
        self.model = g1_model(floor=False)
        qpos = clip_qpos(clip).astype(np.float64)
        qvel, qacc = finite_differences(self.model, qpos, 1.0 / clip.fps)
        bodies = tuple(dict.fromkeys([*G1.feet, *(t.body for t in gains.frames)]))
        ref = motion_reference(self.model, qpos, qvel, qacc, bodies, 1.0 / clip.fps)
        soles = {}
        for f in G1.feet:  # the sole polygon shrunk about its centroid: a margin for the centre of pressure
            poly = sole_polygon(self.model, f)
            centre = poly.mean(axis=0)
            soles[f] = centre + sole_scale * (poly - centre)
        self.qp = WholeBodyQP(
            self.model,
            G1.joints,
            np.asarray(G1.effort),
            soles,
            ref,
            mu=FOOT_FRICTION,
            gains=gains,
            settings=settings,
        )
        self.schedule = np.asarray(clip.contacts if schedule is None else schedule, dtype=bool)
        self.kp, self.kd = np.asarray(G1.kp), np.asarray(G1.kd)
        self.default, self.scale = np.asarray(G1.default_pose), np.asarray(G1.action_scale)
        self.period, self.smoothing, self.balance = period, smoothing, balance
        self.servo_joints = np.array([G1.joints.index(n) for n in servo_joints], dtype=int)
        self.emphasis: list[float] = []
        self.stepping = stepping
        self.soles = soles
        self.offset = np.zeros(3)
        self.step: dict | None = None
        self.steps_taken: list[int] = []
        self.cooldown = 0
        self.adjusted = False
        self.prev_target: np.ndarray | None = None
        self.solve_s: list[float] = []
        self.last = None

    def reset(self) -> None:
        """Forget the previous episode (solver warm start, smoothing state, timings)."""
        self.qp.reset()
        self.prev_target, self.last = None, None
        self.solve_s = []
        self.offset, self.step, self.steps_taken, self.cooldown = np.zeros(3), None, [], 0
        self.adjusted = False

    def _balance_scales(self, qpos: np.ndarray, qvel: np.ndarray, frame: int) -> dict[str, float] | None:
        """Balance emphasis from the divergent component of motion (capture point) error: with
        omega = sqrt(g / z_com), xi = c + v / omega against the reference's; e = |xi - xi_ref| (xy) turns
        the COM's horizontal weight up (x ``1 + (boost - 1) s``) and the posture and frame tasks down
        (x ``1 - (1 - floor) s``), s = clip((e - e0) / (e1 - e0), 0, 1): the upper body may swing (the
        hip strategy) while a push is absorbed."""
        if self.balance is None:
            return None
        e0, e1, boost, floor = self.balance
        d, r = self.qp.data, self.qp.ref
        d.qpos[:], d.qvel[:] = qpos, qvel
        mujoco.mj_kinematics(self.model, d)
        mujoco.mj_comPos(self.model, d)
        f = min(frame, r.frames - 1)
        jc = np.zeros((3, self.model.nv))
        mujoco.mj_jacSubtreeCom(self.model, d, jc, 1)
        c, v = d.subtree_com[1], jc @ d.qvel
        omega = math.sqrt(9.81 / max(c[2], 0.3))
        e = float(np.linalg.norm((c + v / omega - r.com[f] - r.com_vel[f] / omega)[:2]))
        s = min(max((e - e0) / (e1 - e0), 0.0), 1.0)
        self.emphasis.append(s)
        return {
            "com_xy": 1.0 + (boost - 1.0) * s,
            "frames": 1.0 - (1.0 - floor) * s,
            "posture": 1.0 - (1.0 - floor) * s,
        }

    def _capture_step(self, qpos, qvel, f, stance, scales):
        """A step the clip does not have, when a push throws the capture point out of the support.

        In the clip's double stance, with omega = sqrt(g / z_com) and xi = c + v / omega (xy): when xi
        is outside the convex hull of both soles by more than ``margin`` and more than ``error`` from
        the reference's, the foot nearer xi swings for ``duration`` to where the linear inverted
        pendulum on the other sole (centre p) takes xi by then, p + (xi - p) exp(omega T), clamped
        in the stance foot's heading frame; a minimum-jerk path with a (4u(1-u))^2 height bump.
        At touchdown every reference position is shifted by the feet's mean displacement from
        their reference (``offset``), so the clip goes on around the new stance."""
        sp, d, r, m = self.stepping, self.qp.data, self.qp.ref, self.model
        d.qpos[:], d.qvel[:] = qpos, qvel
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        feet = [m.body(b).id for b in G1.feet]
        if self.step is not None:
            st = self.step
            u = (f - st["k0"]) / st["n"]
            if u < 1.0:
                T = st["n"] * POLICY_DT
                s = 10 * u**3 - 15 * u**4 + 6 * u**5
                ds = (30 * u**2 - 60 * u**3 + 30 * u**4) / T
                dds = (60 * u - 180 * u**2 + 120 * u**3) / T**2
                zb = 16 * u**2 * (1 - u) ** 2
                dzb = 16 * (2 * u - 6 * u**2 + 4 * u**3) / T
                ddzb = 16 * (2 - 12 * u + 12 * u**2) / T**2
                dp = st["p1"] - st["p0"]
                pos = st["p0"] + dp * s + np.array([0, 0, sp.height * zb])
                vel = np.concatenate([dp * ds + np.array([0, 0, sp.height * dzb]), np.zeros(3)])
                acc = np.concatenate([dp * dds + np.array([0, 0, sp.height * ddzb]), np.zeros(3)])
                name = G1.feet[st["foot"]]
                stance = np.array([i != st["foot"] for i in range(2)])
                return stance, {name: (pos, st["quat"], vel, acc)}, {**(scales or {}), "com_xy": sp.com_scale}
            self.step = None
            ref_mean = np.mean([r.body_pos[b][f] for b in G1.feet], axis=0)
            self.offset = np.zeros(3)
            self.offset[:2] = (np.mean([d.xpos[b] for b in feet], axis=0) - ref_mean)[:2]
            self.cooldown = f + sp.cooldown
        jc = np.zeros((3, m.nv))
        mujoco.mj_jacSubtreeCom(m, d, jc, 1)
        c = d.subtree_com[1].copy()
        omega = math.sqrt(9.81 / max(c[2], 0.3))
        xi = (c + jc @ qvel / omega)[:2]
        xi_ref = (r.com[f] + self.offset + r.com_vel[f] / omega)[:2]
        if stance[0] != stance[1]:
            return self._adjust_swing(f, stance, scales, xi - xi_ref, omega)
        if self.adjusted and stance[0] and stance[1]:  # a clip step with a moved foothold landed
            self.adjusted = False
            ref_mean = np.mean([r.body_pos[b][f] for b in G1.feet], axis=0)
            self.offset[:2] = (np.mean([d.xpos[b] for b in feet], axis=0) - ref_mean)[:2]
        if not (stance[0] and stance[1]) or f < self.cooldown:
            return stance, None, scales
        centres, verts = [], []
        for i, b in enumerate(feet):
            rot = d.xmat[b].reshape(3, 3)
            w = d.xpos[b] + self.soles[G1.feet[i]] @ rot.T
            verts.append(w[:, :2])
            centres.append(w.mean(axis=0))
        outside = _outside(np.vstack(verts), xi)
        if outside < sp.margin or np.linalg.norm(xi - xi_ref) < sp.error:
            return stance, None, scales
        foot = int(np.argmin([np.linalg.norm(cc[:2] - xi) for cc in centres]))
        other = 1 - foot
        p = centres[other][:2]
        if np.linalg.norm(c[:2] - p) > sp.max_lean:
            return stance, None, scales  # the stance foot could not carry the body through the swing
        T = sp.duration
        land = p + (xi - p) * math.exp(omega * T)
        yaw_rot = d.xmat[feet[other]].reshape(3, 3)
        heading = yaw_rot[:2, 0] / np.linalg.norm(yaw_rot[:2, 0])
        lateral = np.array([-heading[1], heading[0]])
        rel = land - p
        side = 1.0 if foot == 0 else -1.0  # left foot on the +lateral side
        dx = float(np.clip(rel @ heading, -sp.reach[0], sp.reach[1]))
        dy = side * float(np.clip(side * (rel @ lateral), sp.width[0], sp.width[1]))
        target_centre = p + dx * heading + dy * lateral
        b = feet[foot]
        p0 = d.xpos[b].copy()
        sole_off = centres[foot] - d.xpos[b]
        p1 = np.array([*(target_centre - sole_off[:2]), p0[2]])
        self.step = {
            "foot": foot,
            "k0": f,
            "n": max(int(round(T / POLICY_DT)), 2),
            "p0": p0,
            "p1": p1,
            "quat": d.xquat[b].copy(),
        }
        self.steps_taken.append(f)
        return self._capture_step(qpos, qvel, f, stance, scales)

    def _adjust_swing(self, f, stance, scales, e, omega):
        """The clip's own swing foot lands displaced by the capture-point error extrapolated to its
        touchdown, ``e exp(omega (t_td - t))`` (at most ``sp.adjust`` [m], no nearer the stance foot's
        centre line than ``sp.width[0]``), blended in along the swing by a minimum-jerk profile."""
        sp, r, d = self.stepping, self.qp.ref, self.qp.data
        if sp.adjust <= 0 or np.linalg.norm(e) < sp.error:
            return stance, None, scales
        foot = 0 if not stance[0] else 1
        col = self.schedule[:, foot]
        lo = f
        while lo > 0 and not col[lo - 1]:
            lo -= 1
        td = f
        while td < len(col) - 1 and not col[td]:
            td += 1
        if td - lo < 3:
            return stance, None, scales
        shift = e * math.exp(omega * (td - f) * POLICY_DT)
        n = np.linalg.norm(shift)
        if n > sp.adjust:
            shift *= sp.adjust / n
        name = G1.feet[foot]
        other = self.model.body(G1.feet[1 - foot]).id
        land = r.body_pos[name][td][:2] + self.offset[:2] + shift
        lateral = d.xmat[other].reshape(3, 3)[:2, 1]
        lateral /= np.linalg.norm(lateral)
        side = 1.0 if foot == 0 else -1.0
        gap = side * ((land - d.xpos[other][:2]) @ lateral)
        if gap < sp.width[0]:
            shift += side * (sp.width[0] - gap) * lateral
        T = (td - lo) * POLICY_DT
        u = (f - lo) / (td - lo)
        sm = 10 * u**3 - 15 * u**4 + 6 * u**5
        ds = (30 * u**2 - 60 * u**3 + 30 * u**4) / T
        dds = (60 * u - 180 * u**2 + 120 * u**3) / T**2
        delta = np.array([*shift, 0.0])
        pos = r.body_pos[name][f] + self.offset + delta * sm
        vel = r.body_vel[name][f] + np.concatenate([delta * ds, np.zeros(3)])
        acc = r.body_acc[name][f] + np.concatenate([delta * dds, np.zeros(3)])
        self.adjusted = True
        return stance, {name: (pos, r.body_quat[name][f], vel, acc)}, scales

    def targets(self, qpos: np.ndarray, qvel: np.ndarray, frame: int) -> np.ndarray:
        """Servo targets (29) for the true state at reference ``frame``."""
        t0 = time.perf_counter()
        f = min(frame, len(self.schedule) - 1)
        stance, swing, scales = self.schedule[f], None, self._balance_scales(qpos, qvel, frame)
        if self.stepping is not None:
            stance, swing, scales = self._capture_step(qpos, qvel, f, stance, scales)
        sol = self.qp.solve(qpos, qvel, frame, stance, scales, self.offset, swing)
        self.solve_s.append(time.perf_counter() - t0)
        self.last = sol
        j = self.qp.dofs
        t = servo_targets(sol.tau, qpos[self.qp.qadr], qvel[j], sol.qacc[j], self.kp, self.kd, self.period)
        if len(self.servo_joints):
            # the servo's own PD (no latency) about the reference, plus the QP's torque as feedforward
            r, s = self.qp.ref, self.servo_joints
            f = min(frame, r.frames - 1)
            q_ref = r.qpos[f][self.qp.qadr[s]] + r.qvel[f][j[s]] * self.period / 2
            t[s] = q_ref + sol.tau[s] / self.kp[s]
        if self.prev_target is not None and self.smoothing > 0:
            t = self.smoothing * self.prev_target + (1 - self.smoothing) * t
        self.prev_target = t
        return t

    def action(self, env: TrackingEnv) -> np.ndarray:
        """Action of ``env``'s current state (privileged: its true ``qpos``/``qvel``)."""
        target = self.targets(env.data.qpos.copy(), env.data.qvel.copy(), env.frame)
        return (target - self.default) / self.scale
