"""Whole-body QP expert for the G1 (``rle_design.control.wbc``) and its evaluation rollouts.

The expert reads the simulator's true ``qpos``/``qvel`` (privileged) and the clip's contact schedule,
runs the QP on the nominal model (never the perturbed one) once per policy step (50 Hz) and sends
the servo targets through ``TrackingEnv.step`` (so the perturbation's latency queue, gains and
friction act on it as on a policy). ``python -m rle_tasks.f04_motion_tracking.solutions.expert CLIP
--seeds 100 101 --strength 1`` prints U, T, MPJPE and the time per control step.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from rle_design.control.wbc import FrameTask, WbcGains, WholeBodyQP, motion_reference, servo_targets

from ..public.clip import Clip, clip_qpos
from ..public.env import POLICY_DT, TrackingEnv
from ..public.evaluate import EVAL_TIMESTEP, _unstable, tracking_step
from ..public.feasibility import finite_differences, sole_polygon
from ..public.g1 import FOOT_FRICTION, g1_model
from ..public.g1_constants import G1
from ..public.perturb import NOMINAL, Perturbation, sample_perturbation

__all__ = ["DEFAULT_GAINS", "STEPPING", "Expert", "StepParams", "expert_rollout", "with_arm_lead"]

HANDS = ("left_wrist_yaw_link", "right_wrist_yaw_link")
DEFAULT_GAINS = WbcGains(
    contact_kd=20.0,  # the action jerk J on the nominal dance: 0.028 at 10, 0.022 at 20, 0.061 at 40
    frames=(
        FrameTask(G1.anchor_body, pos=0.0, ori=5.0, kp=100.0, kd=20.0),
        FrameTask("pelvis", pos=0.0, ori=2.0, kp=100.0, kd=20.0),
        FrameTask(HANDS[0], pos=1.0, kp=100.0, kd=20.0),
        FrameTask(HANDS[1], pos=1.0, kp=100.0, kd=20.0),
    ),
)


@dataclass(frozen=True)
class StepParams:
    """Capture steps of ``Expert`` (see ``Expert._capture_step``)."""

    margin: float = 0.01
    """The capture point this far outside the soles' hull triggers a step [m]."""
    error: float = 0.04
    """... and this far from the reference's capture point [m]."""
    duration: float = 0.2
    """Swing time [s] (0.26 on the dance's seeds 201 and 204: 0.28 and 0.24 survival instead of 0.65 and 0.24)."""
    height: float = 0.06
    """Swing apex [m]."""
    reach: tuple[float, float] = (0.3, 0.3)
    """Largest step along the stance foot's heading [m] (back, forward)."""
    width: tuple[float, float] = (0.14, 0.4)
    """Lateral distance of the swing sole's centre from the stance sole's [m]."""
    com_scale: float = 0.1
    """COM weight factor during the step."""
    cooldown: int = 5
    """Policy steps after a touchdown before another capture step [1]."""
    adjust: float = 0.0
    """Largest displacement of the clip's own swing foothold by the capture-point error [m] (0: off;
    0.2 on the dance's seeds 200-207: mean score 0.422 against 0.483 without)."""
    max_lean: float = 0.3
    """No step when the COM is further than this from the stance sole's centre (xy) [m]."""


STEPPING = StepParams()


def _outside(points: np.ndarray, x: np.ndarray) -> float:
    """Signed distance of ``x`` outside the convex hull of ``points`` (xy) [m] (negative inside)."""
    from scipy.spatial import ConvexHull

    hull = ConvexHull(points)
    # equations: n . p + c <= 0 inside, unit normals
    return float(np.max(hull.equations[:, :2] @ x + hull.equations[:, 2]))


def with_arm_lead(gains: WbcGains, lead: int) -> WbcGains:
    """``gains`` with the arms' posture and the wrists' positions tracked ``lead`` frames ahead (the
    fight's punches saturate the shoulders; with one or two steps of latency the wrist lags past the
    termination bound)."""
    arms = tuple(i for i, j in enumerate(G1.joints) if any(k in j for k in ("shoulder", "elbow", "wrist")))
    frames = tuple(dataclasses.replace(t, lead=lead) if t.body in HANDS else t for t in gains.frames)
    return dataclasses.replace(gains, frames=frames, posture_lead=lead, lead_joints=arms)


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


def _step_every_substep(env: TrackingEnv, expert: Expert, action: np.ndarray) -> tuple:
    """``TrackingEnv.step`` with the expert's targets recomputed before every physics step."""
    t_end = (env.frame + 1) * POLICY_DT
    while env._pushes and env._pushes[0].time <= t_end:
        env.data.qvel[:2] += env._pushes.pop(0).dv
    env.data.ctrl[:] = expert.default + expert.scale * action
    for i in range(env.substeps):
        if i:
            env.data.ctrl[:] = expert.targets(env.data.qpos.copy(), env.data.qvel.copy(), env.frame)
        mujoco.mj_step(env.model, env.data)
    mujoco.mj_kinematics(env.model, env.data)
    mujoco.mj_comPos(env.model, env.data)
    mujoco.mj_comVel(env.model, env.data)
    env.frame += 1
    env.last_action = action
    info = env.tracking()
    return env.observe(), bool(info.reason), info


def expert_rollout(
    clip: Clip,
    seed: int = 0,
    strength: float = 0.0,
    expert: Expert | None = None,
    record: bool = False,
    perturbation: Perturbation | None = None,
    every_substep: bool = False,
) -> dict:
    """``evaluate.rollout``'s episode (2 ms physics, terrain and perturbation of ``seed`` at ``strength``,
    or ``perturbation``) driven by the expert; with ``record`` the observations and actions per step
    are returned too. ``every_substep``: the expert recomputes its targets every physics step (period 0;
    a diagnostic that bypasses the action queue, so it refuses a perturbation with latency)."""
    model = g1_model(timestep=EVAL_TIMESTEP, terrain=True)
    pert = perturbation
    if pert is None:
        pert = sample_perturbation(np.random.default_rng(seed), model, strength) if strength > 0 else NOMINAL
    env = TrackingEnv(clip, timestep=EVAL_TIMESTEP, perturbation=pert, seed=seed, model=model)
    expert = expert or Expert(clip, period=0.0 if every_substep else POLICY_DT)
    if every_substep and pert.latency:
        raise ValueError("every_substep bypasses the latency queue")
    expert.reset()
    obs = env.reset(0)
    steps = clip.frames - 1
    t_sum, err_sum, survived, fell, reason = 0.0, 0.0, steps, False, ""
    targets, observations, actions = [], [], []
    for k in range(steps):
        a = expert.action(env)
        if record:
            observations.append(obs)
            actions.append(a)
        targets.append(expert.default + expert.scale * a)
        if every_substep:
            obs, term, info = _step_every_substep(env, expert, a)
        else:
            obs, _, term, _, info = env.step(a)
        if _unstable(env.data):
            fell, survived, reason = True, k, "explosion"
            break
        t_sum += tracking_step(info.body_pos_err, info.body_ori_err, info.anchor_pos_err)
        err_sum += info.body_pos_err
        if term:
            fell, survived, reason = True, k + 1, info.reason
            break
    tg = np.asarray(targets)
    jerk = float(np.sqrt(np.mean((tg[2:] - 2 * tg[1:-1] + tg[:-2]) ** 2))) if len(tg) >= 3 else 0.0
    out = {
        "T": t_sum / steps,
        "U": survived / steps,
        "J": jerk,
        "fell": fell,
        "reason": reason,
        "mpjpe_mm": 1e3 * err_sum / max(survived, 1),
        "survived": survived,
        "ms_per_step": 1e3 * float(np.mean(expert.solve_s)) if expert.solve_s else math.nan,
    }
    if record:
        out["obs"], out["actions"] = np.asarray(observations), np.asarray(actions)
    return out


def main() -> None:
    p = argparse.ArgumentParser(description="Evaluate the whole-body QP expert on a clip.")
    p.add_argument("clip", type=Path)
    p.add_argument("--seeds", type=int, nargs="+", default=[0])
    p.add_argument("--strength", type=float, default=0.0)
    p.add_argument("--every-substep", action="store_true", help="recompute every physics step (nominal only)")
    p.add_argument("--arm-lead", type=int, default=0, help="frames the arms track ahead (fight: 2)")
    a = p.parse_args()
    clip = Clip.load(a.clip)
    for seed in a.seeds:
        expert = Expert(
            clip, with_arm_lead(DEFAULT_GAINS, a.arm_lead), period=0.0 if a.every_substep else POLICY_DT
        )
        r = expert_rollout(clip, seed, a.strength, expert=expert, every_substep=a.every_substep)
        print(
            f"seed {seed} strength {a.strength}: U {r['U']:.3f} T {r['T']:.3f} MPJPE {r['mpjpe_mm']:.0f} mm "
            f"J {r['J']:.4f} fell {r['fell']} ({r['reason']}) {r['ms_per_step']:.1f} ms/step",
            flush=True,
        )


if __name__ == "__main__":
    main()
