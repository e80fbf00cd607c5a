"""A small PPO trainer (torch, CPU) for the tracking environment; the agent may change anything here.

The actor is a residual on a fixed base policy: by default open-loop replay, ``(ref_joint_pos -
default) / scale`` (the reference angles of the observation turned into PD targets, a fixed linear map);
with ``--prior PRIOR.pt`` any TorchScript module ``obs (B, 160) -> actions (B, 29)`` (for instance a
model-based controller), which is not trained. To the base it adds an MLP of the normalised observation
whose last layer starts near zero. Observation statistics are running means;
they are part of the exported graph. Generalised advantage estimation, clipped surrogate, time-limit
bootstrapping. ``python -m rle_tasks.f04_motion_tracking.public.ppo --help``.
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import numpy as np
import torch
from torch import nn

from .clip import Clip
from .env import VecTrackingEnv
from .g1 import g1_model
from .g1_constants import G1
from .perturb import sample_perturbation
from .tracking import OBS_DIM

__all__ = ["ActorCritic", "train"]


class ActorCritic(nn.Module):
    """Actor (residual on a base policy: ``prior``, or open-loop replay when None) and critic sharing
    the observation normaliser."""

    def __init__(self, hidden: tuple[int, ...] = (256, 128), log_std: float = -1.2, prior=None) -> None:
        super().__init__()
        self.prior = prior
        if prior is not None:
            for q in prior.parameters():
                q.requires_grad_(False)
        self.register_buffer("obs_mean", torch.zeros(OBS_DIM))
        self.register_buffer("obs_var", torch.ones(OBS_DIM))
        self.register_buffer("count", torch.tensor(1e-4))
        self.register_buffer("default", torch.tensor(G1.default_pose, dtype=torch.float32))
        self.register_buffer("scale", torch.tensor(G1.action_scale, dtype=torch.float32))

        def mlp(out: int) -> nn.Sequential:
            layers, n = [], OBS_DIM
            for h in hidden:
                layers += [nn.Linear(n, h), nn.ELU()]
                n = h
            layers.append(nn.Linear(n, out))
            return nn.Sequential(*layers)

        self.actor, self.critic = mlp(G1.dof), mlp(1)
        with torch.no_grad():
            self.actor[-1].weight.mul_(0.01)
            self.actor[-1].bias.zero_()
        self.log_std = nn.Parameter(torch.full((G1.dof,), log_std))

    def normalise(self, obs: torch.Tensor) -> torch.Tensor:
        return torch.clamp((obs - self.obs_mean) / torch.sqrt(self.obs_var + 1e-8), -10.0, 10.0)

    def mean_action(self, obs: torch.Tensor) -> torch.Tensor:
        if self.prior is not None:
            base = self.prior(obs)
        else:
            base = (obs[:, : G1.dof] - self.default) / self.scale
        return base + self.actor(self.normalise(obs))

    def value(self, obs: torch.Tensor) -> torch.Tensor:
        return self.critic(self.normalise(obs)).squeeze(-1)

    def forward(self, obs: torch.Tensor) -> torch.Tensor:  # the exported graph: deterministic action
        return self.mean_action(obs)

    @torch.no_grad()
    def update_stats(self, obs: torch.Tensor) -> None:
        n = obs.shape[0]
        mean, var = obs.mean(0), obs.var(0, unbiased=False)
        total = self.count + n
        delta = mean - self.obs_mean
        self.obs_mean += delta * n / total
        self.obs_var = (self.obs_var * self.count + var * n + delta**2 * self.count * n / total) / total
        self.count = total


def train(
    clip_path: Path,
    out: Path,
    *,
    seed: int = 0,
    minutes: float = 60.0,
    num_envs: int = 16,
    horizon: int = 32,
    epochs: int = 5,
    minibatches: int = 4,
    lr: float = 3e-4,
    gamma: float = 0.99,
    lam: float = 0.95,
    clip_eps: float = 0.2,
    randomise: float = 1.0,
    prior: Path | None = None,
    log_std: float = -1.2,
    timestep: float = 0.005,
    snapshot_every: int = 0,
) -> ActorCritic:
    """Train on one clip for ``minutes`` of wall time; writes ``out/curve.csv`` and ``out/policy.pt``
    (and ``out/snapshots/<iteration>.pt`` every ``snapshot_every`` iterations when > 0).

    Each environment gets one fixed ``sample_perturbation`` robot of strength ``randomise``; ``prior``
    is a TorchScript base policy (see the module docstring), ``log_std`` the initial log standard
    deviation of the exploration noise, ``timestep`` the physics step [s]."""
    torch.manual_seed(seed)
    torch.set_num_threads(1)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    model = g1_model()
    perts = [sample_perturbation(rng, model, randomise) for _ in range(num_envs)]  # one robot per env
    env = VecTrackingEnv(
        Clip.load(clip_path), num_envs, seed=seed, random_start=True, perturbations=perts, timestep=timestep
    )
    base = torch.jit.load(str(prior)) if prior is not None else None
    net = ActorCritic(log_std=log_std, prior=base)
    opt = torch.optim.Adam([q for q in net.parameters() if q.requires_grad], lr=lr)
    obs = torch.as_tensor(env.reset(), dtype=torch.float32)
    net.update_stats(obs)
    start, it, steps = time.monotonic(), 0, 0
    ep_len = np.zeros(num_envs)
    finished: list[float] = []
    with open(out / "curve.csv", "w", newline="") as fh:
        log = csv.writer(fh)
        log.writerow(["iteration", "env_steps", "wall_s", "mean_reward", "mean_episode_s"])
        while time.monotonic() - start < minutes * 60:
            buf = {k: [] for k in ("obs", "act", "logp", "rew", "val", "done", "boot")}
            for _ in range(horizon):
                with torch.no_grad():
                    mu = net.mean_action(obs)
                    dist = torch.distributions.Normal(mu, net.log_std.exp())
                    act = dist.sample()
                    logp, val = dist.log_prob(act).sum(-1), net.value(obs)
                nobs, rew, term, trunc, _ = env.step(act.numpy())
                nobs_t = torch.as_tensor(nobs, dtype=torch.float32)
                boot = torch.zeros(num_envs)
                if trunc.any():  # time limit: bootstrap with the value of the state it reached
                    last_obs = np.stack([env.final_obs[i] if t else nobs[i] for i, t in enumerate(trunc)])
                    with torch.no_grad():
                        v_end = net.value(torch.as_tensor(last_obs, dtype=torch.float32))
                    boot = torch.as_tensor(trunc, dtype=torch.float32) * gamma * v_end
                for k, v in zip(buf, (obs, act, logp, torch.as_tensor(rew, dtype=torch.float32), val)):
                    buf[k].append(v)
                buf["done"].append(torch.as_tensor(term | trunc, dtype=torch.float32))
                buf["boot"].append(boot)
                ep_len += 1
                for i in np.flatnonzero(term | trunc):
                    finished.append(ep_len[i] * 0.02)
                    ep_len[i] = 0
                obs = nobs_t
                steps += num_envs
            net.update_stats(torch.cat(buf["obs"]))
            with torch.no_grad():
                last = net.value(obs)
            adv = torch.zeros(horizon, num_envs)
            gae = torch.zeros(num_envs)
            for t in reversed(range(horizon)):
                nxt = last if t == horizon - 1 else buf["val"][t + 1]
                r = buf["rew"][t] + buf["boot"][t]
                delta = r + gamma * nxt * (1 - buf["done"][t]) - buf["val"][t]
                gae = delta + gamma * lam * (1 - buf["done"][t]) * gae
                adv[t] = gae
            ret = adv + torch.stack(buf["val"])
            b_obs, b_act = torch.cat(buf["obs"]), torch.cat(buf["act"])
            b_logp, b_adv, b_ret = torch.cat(buf["logp"]), adv.reshape(-1), ret.reshape(-1)
            b_adv = (b_adv - b_adv.mean()) / (b_adv.std() + 1e-8)
            n = b_obs.shape[0]
            for _ in range(epochs):
                perm = torch.randperm(n)
                for mb in perm.chunk(minibatches):
                    dist = torch.distributions.Normal(net.mean_action(b_obs[mb]), net.log_std.exp())
                    ratio = torch.exp(dist.log_prob(b_act[mb]).sum(-1) - b_logp[mb])
                    pg = -torch.min(
                        ratio * b_adv[mb], torch.clamp(ratio, 1 - clip_eps, 1 + clip_eps) * b_adv[mb]
                    )
                    v_loss = (net.value(b_obs[mb]) - b_ret[mb]).pow(2)
                    loss = pg.mean() + 0.5 * v_loss.mean() - 0.001 * dist.entropy().sum(-1).mean()
                    opt.zero_grad()
                    loss.backward()
                    nn.utils.clip_grad_norm_(net.parameters(), 1.0)
                    opt.step()
            it += 1
            mean_ep = float(np.mean(finished[-50:])) if finished else float("nan")
            log.writerow(
                [
                    it,
                    steps,
                    round(time.monotonic() - start, 1),
                    float(torch.stack(buf["rew"]).mean()),
                    mean_ep,
                ]
            )
            fh.flush()
            if it % 10 == 0:
                torch.save(net.state_dict(), out / "policy.pt")
            if snapshot_every and it % snapshot_every == 0:
                (out / "snapshots").mkdir(exist_ok=True)
                torch.save(net.state_dict(), out / "snapshots" / f"{it:06d}.pt")
    torch.save(net.state_dict(), out / "policy.pt")
    return net


def main() -> None:
    p = argparse.ArgumentParser(description="Train a tracking policy with PPO on CPU.")
    p.add_argument("clip", type=Path)
    p.add_argument("out", type=Path)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--minutes", type=float, default=60.0)
    p.add_argument("--envs", type=int, default=16)
    p.add_argument("--prior", type=Path, help="TorchScript base policy (default: open-loop replay)")
    p.add_argument("--log-std", type=float, default=-1.2, help="initial log std of the exploration noise")
    p.add_argument("--timestep", type=float, default=0.005, help="physics step [s]")
    p.add_argument("--randomise", type=float, default=1.0, help="perturbation strength of the robots")
    p.add_argument("--snapshot-every", type=int, default=0, help="keep a snapshot every N iterations")
    p.add_argument("--lr", type=float, default=3e-4, help="Adam learning rate")
    a = p.parse_args()
    train(
        a.clip,
        a.out,
        seed=a.seed,
        minutes=a.minutes,
        num_envs=a.envs,
        prior=a.prior,
        log_std=a.log_std,
        timestep=a.timestep,
        randomise=a.randomise,
        snapshot_every=a.snapshot_every,
        lr=a.lr,
    )


if __name__ == "__main__":
    main()
