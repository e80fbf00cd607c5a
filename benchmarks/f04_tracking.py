"""Family 04 throughput: raw ``mj_step`` of the PD-driven G1, tracking-environment steps (single and
vectorised), ONNX inference per call (one onnxruntime thread) and one full ``04-dance`` verification.

Usage: ``.venv/bin/python -m benchmarks f04_tracking [--steps N] [--envs N] [--no-verify]``. Exit status
1 when the eight-seed verification of the open-loop baseline takes 60 s or more. Measured numbers go in
``rle_tasks/f04_motion_tracking/README.md``.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np

from rle_tasks.f04_motion_tracking.public.clip import Clip
from rle_tasks.f04_motion_tracking.public.env import TrackingEnv, VecTrackingEnv
from rle_tasks.f04_motion_tracking.public.g1 import g1_model
from rle_tasks.f04_motion_tracking.task import clip_path

TARGET_VERIFY_S = 60.0


def raw_steps(n: int, timestep: float) -> float:
    """mj_step/s of the G1 under PD at the default pose, fixed targets."""
    model = g1_model(timestep=timestep)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("default").id)
    data.ctrl[:] = data.qpos[7:]
    t0 = time.perf_counter()
    for _ in range(n):
        mujoco.mj_step(model, data)
        if data.qpos[2] < 0.4:  # fallen: start again so the count stays on a standing robot
            mujoco.mj_resetDataKeyframe(model, data, model.key("default").id)
    return n / (time.perf_counter() - t0)


def env_steps(clip: Clip, n: int, envs: int) -> float:
    """Policy steps/s (all environments together) with zero actions, auto-reset."""
    if envs == 1:
        env = TrackingEnv(clip, random_start=True)
        env.reset()
        t0 = time.perf_counter()
        for _ in range(n):
            _, _, te, tr, _ = env.step(np.zeros(29))
            if te or tr:
                env.reset()
        return n / (time.perf_counter() - t0)
    vec = VecTrackingEnv(clip, envs, random_start=True)
    vec.reset()
    t0 = time.perf_counter()
    for _ in range(max(1, n // envs)):
        vec.step(np.zeros((envs, 29)))
    return max(1, n // envs) * envs / (time.perf_counter() - t0)


def onnx_call_us(hidden: tuple[int, ...], calls: int) -> float:
    """Microseconds per inference of an MLP 160-hidden-29 exported like a submission."""
    import torch

    from rle_tasks.f04_motion_tracking.public.evaluate import onnx_policy
    from rle_tasks.f04_motion_tracking.public.export import export_policy

    layers, n = [], 160
    for h in hidden:
        layers += [torch.nn.Linear(n, h), torch.nn.ELU()]
        n = h
    net = torch.nn.Sequential(*layers, torch.nn.Linear(n, 29))
    with tempfile.TemporaryDirectory() as tmp:
        export_policy(net, tmp)
        policy, _ = onnx_policy(Path(tmp))
        x = np.random.default_rng(0).normal(size=(1, 160)).astype(np.float32)
        policy(x)
        t0 = time.perf_counter()
        for _ in range(calls):
            policy(x)
        return 1e6 * (time.perf_counter() - t0) / calls


def verify_s() -> float:
    from rle_tasks.core.runtime.secrets import load_secret
    from rle_tasks.core.task import VerifyContext
    from rle_tasks.f04_motion_tracking.solutions.baselines import open_loop
    from rle_tasks.f04_motion_tracking.verifier import verify

    with tempfile.TemporaryDirectory() as tmp:
        open_loop(Path(tmp))
        t0 = time.perf_counter()
        verify(Path(tmp), VerifyContext(secret=load_secret(None)), task_id="04-dance")
        return time.perf_counter() - t0


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=5000)
    p.add_argument("--envs", type=int, default=16)
    p.add_argument("--no-verify", action="store_true")
    a = p.parse_args()
    clip = Clip.load(clip_path("dance"))
    for dt in (0.005, 0.002):
        print(f"mj_step, G1 29 PD, dt {dt * 1e3:g} ms: {raw_steps(a.steps, dt):,.0f} steps/s")
    print(f"TrackingEnv (5 ms, 50 Hz): {env_steps(clip, a.steps // 4, 1):,.0f} policy steps/s")
    print(f"VecTrackingEnv x{a.envs}: {env_steps(clip, a.steps // 4, a.envs):,.0f} policy steps/s")
    for hidden in ((256, 128), (512, 256, 128)):
        print(
            f"ONNX MLP 160-{'-'.join(map(str, hidden))}-29, 1 thread: {onnx_call_us(hidden, 2000):.0f} us/call"
        )
    if a.no_verify:
        return 0
    s = verify_s()
    print(f"04-dance verification, open-loop baseline, 8 seeds, jobs 1: {s:.1f} s")
    return int(s >= TARGET_VERIFY_S)


if __name__ == "__main__":
    raise SystemExit(main())
