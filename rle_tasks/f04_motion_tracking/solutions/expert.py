"""Evaluation rollouts of the whole-body QP expert (``expert_tracker.Expert``) and its command line.

The expert sends its servo targets through ``TrackingEnv.step`` (so the perturbation's latency queue,
gains and friction act on it as on a policy). ``python -m rle_tasks.f04_motion_tracking.solutions.expert
CLIP --seeds 100 101 --strength 1`` prints U, T, MPJPE and the time per control step.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import mujoco
import numpy as np

from ..public.clip import Clip
from ..public.env import POLICY_DT, TrackingEnv
from ..public.evaluate import EVAL_TIMESTEP, _unstable, tracking_step
from ..public.g1 import g1_model
from ..public.perturb import NOMINAL, Perturbation, sample_perturbation
from .expert_params import DEFAULT_GAINS, with_arm_lead
from .expert_tracker import Expert

__all__ = ["expert_rollout"]


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
