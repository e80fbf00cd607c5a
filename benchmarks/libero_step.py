"""LIBERO-10 in the side environment: control steps per second with and without rendering (and in a
rendering environment with the views skipped, as between a policy's requests), and the scripted
experts' success rates.

Each ``LiberoEnv`` step crosses the process boundary (the sandboxed side simulator); the rates below
include that round trip. Rendering means both 128 x 128 views (agent and wrist) per step.

    .venv/bin/python -m benchmarks libero_step [--steps 100] [--episodes 10] [--first-init 10]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from rle_tasks.envs.libero import LiberoEnv
from rle_tasks.envs.libero.experts import run_expert, supported


def _rate(render: bool, steps: int, views: bool = True) -> float:
    """Control steps per second; ``views=False`` in a rendering environment skips each step's views
    (the steps an evaluation does not serve to its policy)."""
    with LiberoEnv("libero_10", 0, render=render) as env:
        env.reset(0)
        for _ in range(10):  # the first steps compile robosuite's numba kernels
            env.step(np.zeros(7), views=views)
        t0 = time.perf_counter()
        for _ in range(steps):
            env.step(np.zeros(7), views=views)
        return steps / (time.perf_counter() - t0)


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--steps", type=int, default=100)
    p.add_argument("--episodes", type=int, default=10, help="expert episodes per task")
    p.add_argument("--first-init", type=int, default=10, help="first official initial state used")
    p.add_argument("--out", default="out/bench/libero_step.json")
    a = p.parse_args()
    res: dict = {"steps_per_s": {}, "expert": {}}
    for name, render, views in (
        ("state_only", False, False),
        ("rendered", True, True),
        ("views_skipped", True, False),
    ):
        res["steps_per_s"][name] = round(_rate(render, a.steps, views), 1)
        print(json.dumps(res["steps_per_s"]), flush=True)
    for task_id in range(10):
        with LiberoEnv("libero_10", task_id, render=False) as env:
            env.start()
            if not supported(env.scene()):
                res["expert"][task_id] = "no expert"
                continue
            inits = range(a.first_init, a.first_init + a.episodes)
            ok = [run_expert(env, i, np.random.default_rng([0, task_id, i])).success for i in inits]
            res["expert"][task_id] = f"{sum(ok)}/{len(ok)}"
        print(task_id, res["expert"][task_id], flush=True)
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(res, indent=2))
    print(json.dumps(res, indent=2))
    return 0
