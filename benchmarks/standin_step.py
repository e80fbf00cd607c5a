"""Family 05's bimanual stand-in: control steps per second with and without the two 128 x 128 views,
a reset, and the projected wall time of the full evaluation sets on N workers.

An episode of H steps whose policy is asked every k steps costs H / rate_physics + (H / k) x
(render + latency) [s]; 300 (open) or 225 (robust) episodes over N workers take ceil(n / N)
episodes each. ``--latency`` is the served policy's round trip per request (the reference recipe's
frozen-encoder request costs about 0.03 s on one core).

    .venv/bin/python -m benchmarks standin_step [--steps 200] [--chunk 5] [--latency 0.03]
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

from rle_tasks.envs.standin import TASKS, StandinEnv


def main() -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks standin_step")
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--chunk", type=int, default=5)
    ap.add_argument("--latency", type=float, default=0.03)
    args = ap.parse_args()
    out = {}
    for t, task in enumerate(TASKS):
        env = StandinEnv(t)
        env.reset(0)
        t0 = time.perf_counter()
        env.reset(1)
        reset_s = time.perf_counter() - t0
        hold = np.concatenate([env.state[0:6], [1.0], env.state[8:14], [1.0]])
        t0 = time.perf_counter()
        for _ in range(args.steps):
            env.step(hold)
        step_s = (time.perf_counter() - t0) / args.steps
        t0 = time.perf_counter()
        for _ in range(20):
            env.observe(views=True)
        render_s = (time.perf_counter() - t0) / 20
        h = task.max_steps
        episode_s = h * step_s + math.ceil(h / args.chunk) * (render_s + args.latency)
        out[task.name] = {
            "steps_per_s": round(1.0 / step_s, 1),
            "steps_per_s_rendering_every_step": round(1.0 / (step_s + render_s), 1),
            "render_two_views_ms": round(render_s * 1e3, 2),
            "reset_ms": round(reset_s * 1e3, 2),
            "episode_at_horizon_s": round(episode_s, 2),
        }
    mean_episode = float(np.mean([v["episode_at_horizon_s"] for v in out.values()]))
    projection = {
        f"{track} ({n} episodes), {w} workers": round(math.ceil(n / w) * mean_episode / 60, 1)
        for track, n in (("open", 300), ("robust", 225))
        for w in (1, 2, 16)
    }
    print(json.dumps({"per_task": out, "projected_minutes_at_horizon": projection}, indent=1))
    return 0
