"""Whole-body QP expert for the G1 (``rle_design.control.wbc``) and its evaluation rollouts.

The expert reads the simulator's true ``qpos``/``qvel`` (privileged) and the clip's contact schedule,
runs the QP on the nominal model (never the perturbed one) once per policy step (50 Hz) and sends
the servo targets through ``TrackingEnv.step`` (so the perturbation's latency queue, gains and
friction act on it as on a policy). ``python -m rle_tasks.f04_motion_tracking.solutions.expert CLIP
--seeds 100 101 --strength 1`` prints U, T, MPJPE and the time per control step.
"""

from __future__ import annotations

import argparse
import math
import time
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

__all__ = ["DEFAULT_GAINS", "Expert", "expert_rollout"]

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


class Expert:
    """The QP tracker of one clip on the nominal G1.

    Args:
        clip: The reference.
        gains: QP task weights and gains.
        schedule: (F, 2) contact flags of the feet (default: the clip's stance flags).
        period: Hold time of each servo target [s] (``POLICY_DT`` at 50 Hz).
        sole_scale: The contact polygon is the sole's shrunk by this factor about its centroid [1].
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
            self.model, G1.joints, np.asarray(G1.effort), soles, ref, mu=FOOT_FRICTION, gains=gains
        )
        self.schedule = np.asarray(clip.contacts if schedule is None else schedule, dtype=bool)
        self.kp, self.kd = np.asarray(G1.kp), np.asarray(G1.kd)
        self.default, self.scale = np.asarray(G1.default_pose), np.asarray(G1.action_scale)
        self.period, self.smoothing, self.balance = period, smoothing, balance
        self.emphasis: list[float] = []
        self.prev_target: np.ndarray | None = None
        self.solve_s: list[float] = []
        self.last = None

    def reset(self) -> None:
        """Forget the previous episode (solver warm start, smoothing state, timings)."""
        self.qp.reset()
        self.prev_target, self.last = None, None
        self.solve_s = []

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

    def targets(self, qpos: np.ndarray, qvel: np.ndarray, frame: int) -> np.ndarray:
        """Servo targets (29) for the true state at reference ``frame``."""
        t0 = time.perf_counter()
        f = min(frame, len(self.schedule) - 1)
        sol = self.qp.solve(qpos, qvel, frame, self.schedule[f], self._balance_scales(qpos, qvel, frame))
        self.solve_s.append(time.perf_counter() - t0)
        self.last = sol
        j = self.qp.dofs
        t = servo_targets(sol.tau, qpos[self.qp.qadr], qvel[j], sol.qacc[j], self.kp, self.kd, self.period)
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
    a = p.parse_args()
    clip = Clip.load(a.clip)
    for seed in a.seeds:
        r = expert_rollout(clip, seed, a.strength, every_substep=a.every_substep)
        print(
            f"seed {seed} strength {a.strength}: U {r['U']:.3f} T {r['T']:.3f} MPJPE {r['mpjpe_mm']:.0f} mm "
            f"J {r['J']:.4f} fell {r['fell']} ({r['reason']}) {r['ms_per_step']:.1f} ms/step",
            flush=True,
        )


if __name__ == "__main__":
    main()
