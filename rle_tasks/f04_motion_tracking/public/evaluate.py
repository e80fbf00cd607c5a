"""Design-seed evaluation: the hidden evaluation's episode, on seeds you choose.

``rollout`` runs one episode: the policy tracks the clip from frame 0 at 2 ms physics on the G1
perturbed by ``sample_perturbation(default_rng(seed), model, 1.0)``; it returns the per-seed terms of
the score (T, U, J, fall) and MPJPE. The hidden evaluation calls the same function on seeds derived
from a secret. ``python -m <package>.evaluate POLICY_DIR CLIP.npz --seeds 0 1 2`` evaluates an export
with onnxruntime (one thread).
"""

from __future__ import annotations

import argparse
import math
from collections import deque
from collections.abc import Callable
from pathlib import Path

import mujoco
import numpy as np

from .clip import Clip
from .contract import ONNX, PolicyMeta, read_meta
from .env import TrackingEnv
from .g1 import g1_model
from .perturb import sample_perturbation

__all__ = ["EVAL_TIMESTEP", "J_MAX", "S_ORI", "S_POS", "S_WORLD", "rollout", "seed_score", "tracking_step"]

EVAL_TIMESTEP = 0.002
"""Physics step of the evaluation [s]."""
S_POS = 0.1
"""Body position error scale of T [m]."""
S_ORI = 0.3
"""Body orientation error scale of T [rad]."""
S_WORLD = 0.5
"""World-frame anchor (torso) position error scale of T [m]."""
J_MAX = 0.05
"""Action jerk at which the jerk deduction is full [rad] (RMS second difference of the PD targets)."""
EXPLOSION_QVEL = 200.0
"""A generalised velocity above this [m/s or rad/s], a non-finite state or a MuJoCo instability
warning counts as an explosion."""
MAX_ACTION = 100.0
"""Actions are clipped to this magnitude before they become PD targets [1]."""


class PolicyError(Exception):
    """Raised by a policy callable to end the episode (``code`` names the fault)."""

    def __init__(self, code: str) -> None:
        super().__init__(code)
        self.code = code


def tracking_step(body_pos_err: float, body_ori_err: float, anchor_world_err: float) -> float:
    """Whole-body tracking of one step: the mean of exp(-e_p / S_POS), exp(-e_o / S_ORI) and
    exp(-e_w / S_WORLD) (relative body positions [m] and orientations [rad], world anchor position [m])."""
    return (
        math.exp(-body_pos_err / S_POS)
        + math.exp(-body_ori_err / S_ORI)
        + math.exp(-anchor_world_err / S_WORLD)
    ) / 3.0


def seed_score(t: float, u: float, j: float, fell: bool) -> float:
    """s = 0.7 T + 0.3 U - 0.15 min(J / J_max, 1) - 0.05 F, clipped to [0, 1]."""
    s = 0.7 * t + 0.3 * u - 0.15 * min(j / J_MAX, 1.0) - 0.05 * float(fell)
    return min(max(s, 0.0), 1.0)


def _unstable(data: mujoco.MjData) -> bool:
    warn = data.warning
    bad = warn[mujoco.mjtWarning.mjWARN_BADQACC].number + warn[mujoco.mjtWarning.mjWARN_BADQPOS].number
    return bool(bad) or not np.isfinite(data.qpos).all() or np.abs(data.qvel).max() > EXPLOSION_QVEL


def rollout(
    policy: Callable[[np.ndarray], np.ndarray], meta: PolicyMeta, clip: Clip, seed: int, strength: float = 1.0
) -> dict:
    """One evaluation episode.

    Args:
        policy: (1, 160 H) float32 -> (29,) actions; may raise ``PolicyError``.
        meta: History length, action scale and default pose of the policy.
        clip: The reference.
        seed: Seed of the perturbation and the sensor noise.
        strength: Of the perturbation (1: the hidden evaluation's; lower for a training curriculum).

    Returns:
        ``T``, ``U``, ``J``, ``fell``, ``mpjpe_mm``, ``steps``, ``survived``, ``fault`` (code or ''),
        ``explosion_step`` (-1 if none).
    """
    model = g1_model(timestep=EVAL_TIMESTEP, terrain=True)
    pert = sample_perturbation(np.random.default_rng(seed), model, strength)
    env = TrackingEnv(clip, timestep=EVAL_TIMESTEP, perturbation=pert, seed=seed, model=model)
    obs = env.reset(0)
    hist = deque([obs] * meta.history, maxlen=meta.history)
    default, scale = np.asarray(meta.default_pose), np.asarray(meta.action_scale)
    steps = clip.frames - 1
    t_sum, err_sum, survived, fell, fault, explosion = 0.0, 0.0, steps, False, "", -1
    targets = []
    for k in range(steps):
        try:
            a = np.asarray(policy(np.concatenate(list(hist))[None].astype(np.float32)), np.float64).reshape(
                -1
            )
        except PolicyError as exc:
            fault, fell, survived = exc.code, True, k
            break
        target = default + scale * np.clip(a, -MAX_ACTION, MAX_ACTION)
        targets.append(target)
        obs, _, term, _, info = env.step((target - env.default) / env.scale)
        if _unstable(env.data):
            explosion, fell, survived = k, True, k
            break
        hist.append(obs)
        t_sum += tracking_step(info.body_pos_err, info.body_ori_err, info.anchor_pos_err)
        err_sum += info.body_pos_err
        if term:
            fell, survived = True, k + 1
            break
    tg = np.asarray(targets)
    jerk = float(np.sqrt(np.mean((tg[2:] - 2 * tg[1:-1] + tg[:-2]) ** 2))) if len(tg) >= 3 else 0.0
    return {
        "T": t_sum / steps,
        "U": survived / steps,
        "J": jerk,
        "fell": fell,
        "mpjpe_mm": 1e3 * err_sum / max(survived, 1),
        "steps": steps,
        "survived": survived,
        "fault": fault,
        "explosion_step": explosion,
    }


def onnx_policy(policy_dir: Path) -> tuple[Callable[[np.ndarray], np.ndarray], PolicyMeta]:
    """An onnxruntime (one thread) callable of an exported policy directory, and its meta."""
    import onnxruntime as ort

    meta = read_meta(policy_dir)
    opts = ort.SessionOptions()
    opts.intra_op_num_threads = opts.inter_op_num_threads = 1
    sess = ort.InferenceSession(str(Path(policy_dir) / ONNX), opts, providers=["CPUExecutionProvider"])

    def run(x: np.ndarray) -> np.ndarray:
        a = sess.run(["actions"], {"obs": x})[0][0]
        if not np.isfinite(a).all():
            raise PolicyError("onnx.nonfinite")
        return a

    return run, meta


def main() -> None:
    p = argparse.ArgumentParser(description="Evaluate an exported policy on design seeds.")
    p.add_argument("policy_dir", type=Path)
    p.add_argument("clip", type=Path)
    p.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 3])
    a = p.parse_args()
    policy, meta = onnx_policy(a.policy_dir)
    clip = Clip.load(a.clip)
    scores = []
    for seed in a.seeds:
        r = rollout(policy, meta, clip, seed)
        scores.append(seed_score(r["T"], r["U"], r["J"], r["fell"]))
        print(
            f"seed {seed}: s {scores[-1]:.3f} T {r['T']:.3f} U {r['U']:.3f} J {r['J']:.4f} MPJPE {r['mpjpe_mm']:.0f} mm"
        )
    print(f"mean {np.mean(scores):.3f}")


if __name__ == "__main__":
    main()
