"""DAgger distillation of the whole-body QP expert (``expert_tracker.py``) into an ONNX MLP policy.

Iteration i: every episode runs ``TrackingEnv`` (2 ms physics, a ``sample_perturbation`` robot at
``--strength``, a random start frame, at most ``--steps`` policy steps); each step the expert labels the
true state with its action, and the executed action is the expert's with probability ``beta^i`` and the
student's otherwise (iteration 0: the expert alone). The labelled (observation history, expert action)
pairs are aggregated over iterations and the student, an ELU MLP on normalised observations
(``160 H -> hidden -> 29``), is refitted on all of them (MSE, Adam). Episodes fan out over ``--workers``
processes (spawned; each episode builds its robot, noise and expert solver from its own seed and the
results are gathered in submission order), so the result does not depend on the number of workers.
Torch runs on the CPU with one thread per process.

    python -m rle_tasks.f04_motion_tracking.solutions.distil CLIP.npz OUT --workers 16 --iterations 10

writes ``OUT/policy`` (``policy.onnx`` + ``policy_meta.json``, via ``public.export``) and ``OUT/student.pt``
of the best student so far on the design seeds ``--eval-seeds`` (by score, then survival; the latest
without them), and ``OUT/log.csv`` (per iteration: samples, loss, the student's design-seed U, T and
score).
"""

from __future__ import annotations

import argparse
import csv
import multiprocessing as mp
import time
from collections import deque
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..public.clip import Clip
from ..public.env import TrackingEnv
from ..public.evaluate import EVAL_TIMESTEP, MAX_ACTION, rollout, seed_score
from ..public.export import default_meta, export_policy
from ..public.g1 import g1_model
from ..public.perturb import NOMINAL, sample_perturbation

__all__ = ["Episode", "collect", "fit", "main"]

SEED_OFFSET = 1_000_000
"""Episode perturbation seeds start here (away from the design seeds 100-207)."""
_EXPERTS: dict = {}


@dataclass(frozen=True)
class Episode:
    """One data-collection job (picklable)."""

    clip: str
    seed: int
    strength: float
    beta: float
    steps: int
    history: int
    weights: list | None  # the student's (W, b) per layer and the normaliser, numpy; None: expert only


def _expert(clip_path: str):
    from .expert_tracker import Expert

    if clip_path not in _EXPERTS:  # per process: the reference is precomputed once
        clip = Clip.load(clip_path)
        _EXPERTS[clip_path] = (clip, Expert(clip))
    return _EXPERTS[clip_path]


def _student_np(weights: list):
    """The MLP's forward pass in numpy (float64): ``weights = [mean, std, (W, b), ...]``."""
    mean, std, layers = weights[0], weights[1], weights[2:]

    def act(x: np.ndarray) -> np.ndarray:
        h = (np.asarray(x, np.float64).reshape(-1) - mean) / std
        for i, (w, b) in enumerate(layers):
            h = h @ w + b
            if i < len(layers) - 1:
                h = np.where(h > 0, h, np.expm1(np.minimum(h, 0)))  # ELU
        return h

    return act


def collect(job: Episode) -> tuple[np.ndarray, np.ndarray, int]:
    """Run one DAgger episode; returns (observation histories, expert actions, steps survived)."""
    clip, expert = _expert(job.clip)
    rng = np.random.default_rng(job.seed)
    model = g1_model(timestep=EVAL_TIMESTEP, terrain=True)
    pert = (
        sample_perturbation(np.random.default_rng(job.seed), model, job.strength) if job.strength else NOMINAL
    )
    env = TrackingEnv(clip, timestep=EVAL_TIMESTEP, perturbation=pert, seed=job.seed, model=model)
    start = int(rng.integers(0, max(clip.frames - job.steps - 1, 1)))
    expert.reset()
    obs = env.reset(start)
    hist = deque([obs] * job.history, maxlen=job.history)
    student = _student_np(job.weights) if job.weights is not None else None
    xs, ys = [], []
    for k in range(min(job.steps, clip.frames - 1 - start)):
        x = np.concatenate(list(hist)).astype(np.float32)
        label = expert.action(env)
        if not np.all(np.isfinite(label)) or np.abs(label).max() > MAX_ACTION:
            break  # the expert lost the robot (its QP far from the reference): no label, episode over
        xs.append(x)
        ys.append(label.astype(np.float32))
        a = label if student is None or rng.random() < job.beta else student(x)
        obs, _, term, trunc, _ = env.step(a)
        hist.append(obs)
        if term or trunc:
            return np.asarray(xs), np.asarray(ys), k + 1
    return np.asarray(xs), np.asarray(ys), len(xs)


def _evaluate(item: tuple[str, list, int, int]) -> dict:
    clip_path, weights, seed, history = item
    act = _student_np(weights)
    return rollout(lambda x: act(x), default_meta(history), Clip.load(clip_path), seed)


def _mlp(n_in: int, hidden: tuple[int, ...], mean: np.ndarray, std: np.ndarray):
    import torch

    class Student(torch.nn.Module):
        def __init__(self) -> None:
            super().__init__()
            self.register_buffer("mean", torch.as_tensor(mean, dtype=torch.float32))
            self.register_buffer("std", torch.as_tensor(std, dtype=torch.float32))
            dims = (n_in, *hidden, 29)
            layers: list = []
            for i in range(len(dims) - 1):
                layers.append(torch.nn.Linear(dims[i], dims[i + 1]))
                if i < len(dims) - 2:
                    layers.append(torch.nn.ELU())
            self.net = torch.nn.Sequential(*layers)

        def forward(self, obs):
            return self.net((obs - self.mean) / self.std)

    return Student()


def fit(
    x: np.ndarray,
    y: np.ndarray,
    hidden: tuple[int, ...],
    epochs: int,
    seed: int,
    lr: float = 1e-3,
    device: str = "cpu",
):
    """A fresh student fitted to (x, y) by MSE on ``device`` (``cpu``; ``cuda`` where a GPU is lent:
    faster, not bit-reproducible); returns it, on the CPU, and its final epoch's mean loss."""
    import torch

    torch.manual_seed(seed)
    mean, std = x.mean(axis=0), x.std(axis=0) + 1e-3
    net = _mlp(x.shape[1], hidden, mean, std).to(device)
    opt = torch.optim.Adam(net.parameters(), lr=lr)
    xt, yt = torch.as_tensor(x, device=device), torch.as_tensor(y, device=device)
    gen = torch.Generator().manual_seed(seed)
    batch, loss_sum = 512, 0.0
    for _ in range(epochs):
        perm = torch.randperm(len(xt), generator=gen).to(device)
        loss_sum, count = 0.0, 0
        for i in range(0, len(xt), batch):
            idx = perm[i : i + batch]
            loss = torch.nn.functional.mse_loss(net(xt[idx]), yt[idx])
            opt.zero_grad()
            loss.backward()
            opt.step()
            loss_sum, count = loss_sum + loss.item() * len(idx), count + len(idx)
        loss_sum /= max(count, 1)
    return net.cpu(), loss_sum


def _weights(net) -> list:
    lin = [m for m in net.net if hasattr(m, "weight")]
    return [net.mean.numpy().astype(np.float64), net.std.numpy().astype(np.float64)] + [
        (m.weight.detach().numpy().T.astype(np.float64), m.bias.detach().numpy().astype(np.float64))
        for m in lin
    ]


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description="DAgger distillation of the QP expert into an ONNX policy.")
    p.add_argument("clip", type=Path)
    p.add_argument("out", type=Path)
    p.add_argument("--workers", type=int, default=1)
    p.add_argument("--iterations", type=int, default=10)
    p.add_argument("--episodes", type=int, default=16, help="per iteration")
    p.add_argument("--steps", type=int, default=250, help="policy steps per episode at most")
    p.add_argument("--strength", type=float, default=1.0)
    p.add_argument("--beta", type=float, default=0.5, help="expert execution probability beta^i")
    p.add_argument("--history", type=int, default=1)
    p.add_argument("--hidden", type=int, nargs="+", default=[512, 256, 128])
    p.add_argument("--epochs", type=int, default=30)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--eval-seeds", type=int, nargs="*", default=[200, 201])
    p.add_argument(
        "--low-pass", type=float, default=0.0, help="output low-pass weight s of the export (public.export)"
    )
    p.add_argument("--fit-threads", type=int, default=1, help="torch threads of the fit (collection idles)")
    p.add_argument("--device", default="cpu", help="where the fit runs: cpu, or cuda where a GPU is lent")
    p.add_argument(
        "--deadline-s",
        type=float,
        default=0.0,
        help="start no iteration that would end past this [s] (0: none)",
    )
    a = p.parse_args(argv)
    import torch

    torch.set_num_threads(a.fit_threads)
    start, last, best = time.time(), 0.0, (-1.0, -1.0)
    a.out.mkdir(parents=True, exist_ok=True)
    clip = str(a.clip.resolve())
    ctx = mp.get_context("spawn")
    pool = ctx.Pool(a.workers, initializer=_init_worker) if a.workers > 1 else None
    run = pool.map if pool is not None else lambda f, items: [f(i) for i in items]
    xs: list[np.ndarray] = []
    ys: list[np.ndarray] = []
    weights, net = None, None
    with open(a.out / "log.csv", "w", newline="") as fh:
        log = csv.writer(fh)
        log.writerow(["iteration", "samples", "mean_steps", "loss", "U", "T", "score", "seconds"])
        for it in range(a.iterations):
            t0 = time.time()
            if a.deadline_s and it > 0 and t0 - start + 1.2 * last > a.deadline_s:
                print(
                    f"iteration {it}: not started, the next would end past {a.deadline_s:.0f} s", flush=True
                )
                break
            beta = 1.0 if it == 0 else a.beta**it
            jobs = [
                Episode(
                    clip,
                    SEED_OFFSET + 1000 * (a.seed * 1000 + it) + e,
                    a.strength,
                    beta,
                    a.steps,
                    a.history,
                    weights,
                )
                for e in range(a.episodes)
            ]
            results = run(collect, jobs)
            xs += [r[0] for r in results if len(r[0])]
            ys += [r[1] for r in results if len(r[1])]
            x, y = np.concatenate(xs), np.concatenate(ys)
            net, loss = fit(x, y, tuple(a.hidden), a.epochs, a.seed * 1000 + it, device=a.device)
            weights = _weights(net)
            evals = (
                run(_evaluate, [(clip, weights, s, a.history) for s in a.eval_seeds]) if a.eval_seeds else []
            )
            u = float(np.mean([r["U"] for r in evals])) if evals else float("nan")
            t = float(np.mean([r["T"] for r in evals])) if evals else float("nan")
            score = (
                float(np.mean([seed_score(r["T"], r["U"], r["J"], r["fell"]) for r in evals]))
                if evals
                else float("nan")
            )
            steps = float(np.mean([r[2] for r in results]))
            log.writerow(
                [
                    it,
                    len(x),
                    f"{steps:.1f}",
                    f"{loss:.5f}",
                    f"{u:.3f}",
                    f"{t:.3f}",
                    f"{score:.3f}",
                    f"{time.time() - t0:.0f}",
                ]
            )
            fh.flush()
            print(
                f"iteration {it}: {len(x)} samples, episode {steps:.0f} steps, loss {loss:.4f}, U {u:.3f} T {t:.3f} score {score:.3f}",
                flush=True,
            )
            if not a.eval_seeds or (score, u) >= best:  # the best student on the design seeds so far
                best = (score, u)
                export_policy(net, a.out / "policy", default_meta(a.history), smoothing=1.0 - a.low_pass)
                torch.save(net.state_dict(), a.out / "student.pt")
            last = time.time() - t0
    if pool is not None:
        pool.close()
        pool.join()


def _init_worker() -> None:
    import os

    os.environ.setdefault("OMP_NUM_THREADS", "1")
    try:
        import torch

        torch.set_num_threads(1)
    except ImportError:
        pass


if __name__ == "__main__":
    main()
