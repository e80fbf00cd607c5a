"""Family 07: verification time of the eight hidden piles beside its physics floor.

The verification is timed as the verifier runs it (load and smoke test, then every pile through the
core fan-out). The floor is plain ``mujoco.mj_step`` of each pile's scene for the same simulated
seconds (C loop, no Python per step) plus rendering the same frames (both cameras every 0.1 s); the
piles' construction (dump and settle) is reported apart. The reference policy's own compute (CPU time
of its sandboxed child) is excluded from the ratio. Targets: ratio <= 1.5 and the eight piles under
10 minutes with ``--jobs 2`` on this machine.

    .venv/bin/python -m benchmarks f07_verify [--quick] [--jobs N] [--dir DIR]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import mujoco

from rle_tasks.core.runtime.parallel import run_parallel
from rle_tasks.core.runtime.secrets import load_secret
from rle_tasks.core.solutions import materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f07_bin_clearing.public.env import make_env, render_cameras
from rle_tasks.f07_bin_clearing.public.workcell import CAMERA_HZ
from rle_tasks.f07_bin_clearing.scoring import EPISODE_S, QUICK_EPISODE_S, pile_score
from rle_tasks.f07_bin_clearing.verifier import POLICY_FILE, PileUnit, _load_and_smoke, hidden_piles, run_pile


def _floor(pile, seconds: float) -> tuple[float, float]:
    """(physics [s], rendering [s]) of the pile's scene for ``seconds`` simulated."""
    env = make_env(pile)
    model = env.build()
    data = mujoco.MjData(model)
    env.reset(model, data)
    render_cameras(model, data)  # GL context outside the timing, as in a warm verifier
    per_frame = int(round(1.0 / (CAMERA_HZ * model.opt.timestep)))
    n_frames = int(round(seconds * CAMERA_HZ))
    physics = render = 0.0
    for _ in range(n_frames):
        t0 = time.perf_counter()
        mujoco.mj_step(model, data, per_frame)
        t1 = time.perf_counter()
        render_cameras(model, data)
        t2 = time.perf_counter()
        physics, render = physics + t1 - t0, render + t2 - t1
    return physics, render


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--dir", default=None, help="artifact directory (default: the shipped reference)")
    p.add_argument("--quick", action="store_true")
    p.add_argument("--jobs", type=int, default=1)
    p.add_argument("--out", default="out/bench/f07_verify.json")
    a = p.parse_args()
    root = Path(a.dir) if a.dir else materialise("07-bin-clearing", "reference")
    ctx = VerifyContext(secret=load_secret(), quick=a.quick, jobs=a.jobs)
    seconds = QUICK_EPISODE_S if a.quick else EPISODE_S
    piles = hidden_piles(ctx)
    t0 = time.perf_counter()
    from rle_tasks.core.report import Findings

    cap = _load_and_smoke(root / POLICY_FILE, ctx.hang_cap_s, Findings())
    t_smoke = time.perf_counter() - t0
    items = [PileUnit(str(root / POLICY_FILE), pile, ctx.hang_cap_s, seconds) for pile in piles]
    results = run_parallel(run_pile, items, jobs=a.jobs)
    wall = time.perf_counter() - t0
    t_build = time.perf_counter()
    for pile in piles:
        make_env.__wrapped__(pile)
    build = time.perf_counter() - t_build
    floors = [_floor(pile, seconds) for pile in piles]
    physics, render = sum(f[0] for f in floors), sum(f[1] for f in floors)
    policy_cpu = sum(r["timing"]["policy_cpu_s"] for r in results)
    episodes = sum(r["timing"]["episode_wall_s"] for r in results)
    res = {
        "piles": len(piles),
        "jobs": a.jobs,
        "quick": a.quick,
        "smoke_ok": cap is None,
        "cleared": [r["events"]["cleared"] for r in results],
        "pile_scores": [round(pile_score(r["events"]), 4) for r in results],
        "score": round(sum(pile_score(r["events"]) for r in results) / len(results), 4),
        "events": [
            {k: r["events"][k] for k in ("makespan_s", "N_floor", "N_damage", "N_bin", "blocked_nest")}
            for r in results
        ],  # fmt: skip
        "n_parts": [r["events"]["n_parts"] for r in results],
        "verify_wall_s": round(wall, 2),
        "smoke_s": round(t_smoke, 2),
        "episodes_s": round(episodes, 2),
        "policy_cpu_s": round(policy_cpu, 2),
        "pile_build_s": round(build, 2),
        "floor_physics_s": round(physics, 2),
        "floor_render_s": round(render, 2),
        "ratio_episodes_minus_policy_to_floor": round((episodes - policy_cpu) / (physics + render), 2),
        "targets": {"ratio_max": 1.5, "verify_max_s_jobs2": 600.0},
    }
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(res, indent=2))
    print(json.dumps(res, indent=2))
    ok = res["ratio_episodes_minus_policy_to_floor"] <= 1.5 and (a.jobs < 2 or wall < 600.0)
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
