"""Motion-tracking environment of the G1 on CPU MuJoCo (Gymnasium-style ``reset``/``step``).

Training runs 5 ms physics under a 50 Hz policy (4 substeps); the evaluation 2 ms (10 substeps).
An action a (29) sets the PD targets ``default_pose + action_scale * a``. The observation and the
reward are those of ``tracking``; the episode ends on a ``TERMINATION`` bound (terminated) or at the
clip's last frame (truncated). ``VecTrackingEnv`` steps N environments and resets finished ones.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.rollout import advance

from .clip import Clip
from .g1 import g1_model
from .g1_constants import G1
from .perturb import NOMINAL, Perturbation
from .tracking import (
    ACTION_RATE_WEIGHT,
    END_EFFECTORS,
    JOINT_LIMIT_WEIGHT,
    OBS_DIM,
    REWARD_TERMS,
    SOFT_LIMIT_FACTOR,
    TERMINATION,
    _conj,
    _mul,
    _rotate,
    kernel,
    observation,
    quat_angle,
    quat_angles,
    quat_mul,
    relative_reference,
)

__all__ = ["POLICY_DT", "TrackingEnv", "VecTrackingEnv", "StepInfo"]

POLICY_DT = 0.02
"""Policy period [s] (the clips' 50 Hz)."""


@dataclass(frozen=True)
class StepInfo:
    """Diagnostics of one policy step."""

    terms: dict[str, float]
    """Each reward term's unweighted value."""
    body_pos_err: float
    """Mean over tracked bodies of the position error to the re-anchored reference [m]."""
    body_ori_err: float
    """Mean over tracked bodies of the orientation error [rad]."""
    anchor_pos_err: float
    """Global anchor position error [m]."""
    reason: str
    """Termination bound hit ('' if none)."""


class TrackingEnv:
    """One G1 tracking one clip.

    Args:
        clip: The reference.
        timestep: Physics step [s].
        perturbation: Model and signal perturbation of this environment.
        seed: Seed of the noise generator and of random start frames.
        random_start: Start episodes at a uniformly drawn frame (training) instead of frame 0.
    """

    def __init__(
        self,
        clip: Clip,
        *,
        timestep: float = 0.005,
        perturbation: Perturbation = NOMINAL,
        seed: int = 0,
        random_start: bool = False,
        model: mujoco.MjModel | None = None,
    ) -> None:
        self.clip = clip
        self.model = model if model is not None else g1_model(timestep=timestep)
        self.model.opt.timestep = timestep
        self.pert = perturbation
        self.pert.apply(self.model)
        self.data = mujoco.MjData(self.model)
        self.substeps = int(round(POLICY_DT / timestep))
        self.rng = np.random.default_rng(seed)
        self.random_start = random_start
        self.anchor = self.model.body(G1.anchor_body).id
        self.ref_anchor = G1.tracked_bodies.index(G1.anchor_body)
        self.bodies = np.array([self.model.body(b).id for b in G1.tracked_bodies])
        self.ee = np.array([G1.tracked_bodies.index(b) for b in END_EFFECTORS])
        self.default = np.asarray(G1.default_pose)
        self.scale = np.asarray(G1.action_scale)
        jr = self.model.jnt_range[[self.model.joint(j).id for j in G1.joints]]
        mid, half = jr.mean(axis=1), 0.5 * (jr[:, 1] - jr[:, 0]) * SOFT_LIMIT_FACTOR
        self.soft_lo, self.soft_hi = mid - half, mid + half
        self.frame = 0
        self.last_action = np.zeros(G1.dof)
        self.queue: deque[np.ndarray] = deque()
        self._pushes: list = []

    # -- state ------------------------------------------------------------------------------------
    def reset(self, frame: int | None = None) -> np.ndarray:
        """Put the robot at the reference state of ``frame`` (default: 0, or random when training)."""
        if frame is None:
            frame = int(self.rng.integers(0, self.clip.frames - 50)) if self.random_start else 0
        self.frame = frame
        c, d, m = self.clip, self.data, self.model
        mujoco.mj_resetData(m, d)
        d.qpos[:] = c.qpos(frame)
        pelvis = G1.tracked_bodies.index("pelvis")
        d.qvel[:3] = c.body_lin_vel_w[frame, pelvis]
        d.qvel[3:6] = _rotate(_conj(c.root_quat[frame]), c.body_ang_vel_w[frame, pelvis])
        d.qvel[6:] = c.joint_vel[frame]
        d.ctrl[:] = c.joint_pos[frame]
        mujoco.mj_forward(m, d)
        self.last_action = np.zeros(G1.dof)
        self.queue = deque(np.zeros(G1.dof) for _ in range(self.pert.latency))
        self._pushes = [p for p in self.pert.pushes if p.time > frame * POLICY_DT]
        return self.observe()

    def observe(self) -> np.ndarray:
        """The 160-D observation of the current state (with this environment's sensor perturbation)."""
        c, d, f = self.clip, self.data, self.frame
        noise = self.pert.noise_std

        def n(key: str, size: int) -> np.ndarray:
            std = float(noise.get(key, 0.0))
            return self.rng.normal(0.0, std, size) if std > 0 else np.zeros(size)

        bias = np.asarray(self.pert.encoder_bias) if self.pert.encoder_bias else 0.0
        lin = _rotate(_conj(d.qpos[3:7]), d.qvel[:3])
        return observation(
            c.joint_pos[f],
            c.joint_vel[f],
            c.body_pos_w[f, self.ref_anchor],
            c.body_quat_w[f, self.ref_anchor],
            d.xpos[self.anchor].copy(),
            d.xquat[self.anchor].copy(),
            lin + n("lin_vel", 3),
            d.qvel[3:6] + n("ang_vel", 3),
            d.qpos[7:] - self.default + bias + n("joint_pos", G1.dof),
            d.qvel[6:] + n("joint_vel", G1.dof),
            self.last_action,
        )

    def tracking(self) -> StepInfo:
        """Reward terms, errors and termination of the current state against the current frame."""
        c, d, f = self.clip, self.data, self.frame
        ref_pos, ref_quat = c.body_pos_w[f], c.body_quat_w[f]
        anchor_pos, anchor_quat = d.xpos[self.anchor], d.xquat[self.anchor]
        rel_pos, rel_quat = relative_reference(ref_pos, ref_quat, self.ref_anchor, anchor_pos, anchor_quat)
        pos, quat = d.xpos[self.bodies], d.xquat[self.bodies]
        # velocities of the body frame origins: cvel is (angular, linear) about the subtree COM of the root
        cvel = d.cvel[self.bodies]
        ang = cvel[:, :3]
        lin = cvel[:, 3:] + np.cross(ang, pos - d.subtree_com[self.model.body_rootid[self.bodies]])
        ori = quat_angles(quat_mul(rel_quat, quat * np.array([1.0, -1.0, -1.0, -1.0])))
        anchor_ori = quat_angle(_mul(ref_quat[self.ref_anchor], _conj(anchor_quat)))
        pos_err = np.linalg.norm(rel_pos - pos, axis=1)
        anchor_err = float(np.linalg.norm(ref_pos[self.ref_anchor] - anchor_pos))
        err_sq = {
            "anchor_pos": anchor_err**2,
            "anchor_ori": anchor_ori**2,
            "body_pos": float(np.mean(pos_err**2)),
            "body_ori": float(np.mean(ori**2)),
            "body_lin_vel": float(np.mean(np.sum((c.body_lin_vel_w[f] - lin) ** 2, axis=1))),
            "body_ang_vel": float(np.mean(np.sum((c.body_ang_vel_w[f] - ang) ** 2, axis=1))),
        }
        terms = {t.name: kernel(err_sq[t.name], t.sigma) for t in REWARD_TERMS}
        g_ref = _rotate(_conj(ref_quat[self.ref_anchor]), np.array([0.0, 0.0, -1.0]))[2]
        g_rob = _rotate(_conj(anchor_quat), np.array([0.0, 0.0, -1.0]))[2]
        reason = ""
        if abs(ref_pos[self.ref_anchor, 2] - anchor_pos[2]) > TERMINATION["anchor_height"]:
            reason = "anchor_height"
        elif abs(g_ref - g_rob) > TERMINATION["anchor_gravity_z"]:
            reason = "anchor_gravity_z"
        elif np.abs(rel_pos[self.ee, 2] - pos[self.ee, 2]).max() > TERMINATION["end_effector_height"]:
            reason = "end_effector_height"
        return StepInfo(terms, float(pos_err.mean()), float(ori.mean()), anchor_err, reason)

    # -- dynamics ---------------------------------------------------------------------------------
    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, StepInfo]:
        """Apply one action for one policy period; returns (obs, reward, terminated, truncated, info)."""
        action = np.asarray(action, dtype=np.float64).reshape(G1.dof)
        self.queue.append(action.copy())
        applied = self.queue.popleft()
        t_end = (self.frame + 1) * POLICY_DT
        while self._pushes and self._pushes[0].time <= t_end:
            self.data.qvel[:2] += self._pushes.pop(0).dv
        advance(self.model, self.data, self.default + self.scale * applied, self.substeps)
        # mj_step leaves the kinematics of the state before its last integration: refresh them
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_comPos(self.model, self.data)
        mujoco.mj_comVel(self.model, self.data)
        self.frame += 1
        info = self.tracking()
        reward = sum(t.weight * info.terms[t.name] for t in REWARD_TERMS)
        reward += ACTION_RATE_WEIGHT * float(np.sum((action - self.last_action) ** 2))
        q = self.data.qpos[7:]
        reward += JOINT_LIMIT_WEIGHT * float(
            np.sum(np.maximum(self.soft_lo - q, 0) + np.maximum(q - self.soft_hi, 0))
        )
        self.last_action = action
        terminated = bool(info.reason)
        truncated = self.frame >= self.clip.frames - 1
        return self.observe(), float(reward), terminated, truncated, info


class VecTrackingEnv:
    """N ``TrackingEnv``s stepped together; an environment that ends is reset at once (its returned
    observation is the new episode's first; ``final_obs[i]`` keeps the last one, for bootstrapping)."""

    def __init__(self, clip: Clip, n: int, *, seed: int = 0, perturbations=None, **kwargs) -> None:
        perts = perturbations or [NOMINAL] * n
        self.envs = [TrackingEnv(clip, seed=seed + i, perturbation=perts[i], **kwargs) for i in range(n)]
        self.num_envs = n
        self.observation_dim, self.action_dim = OBS_DIM, G1.dof
        self.final_obs: list[np.ndarray | None] = [None] * n

    def reset(self) -> np.ndarray:
        return np.stack([e.reset() for e in self.envs])

    def step(
        self, actions: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, list[StepInfo]]:
        obs, rew, term, trunc, infos = [], [], [], [], []
        self.final_obs = [None] * self.num_envs
        for i, (env, a) in enumerate(zip(self.envs, actions)):
            o, r, te, tr, info = env.step(a)
            if te or tr:
                self.final_obs[i] = o
                o = env.reset()
            obs.append(o)
            rew.append(r)
            term.append(te)
            trunc.append(tr)
            infos.append(info)
        return np.stack(obs), np.array(rew), np.array(term), np.array(trunc), infos
