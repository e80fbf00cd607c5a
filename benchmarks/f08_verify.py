"""Family 08: full verification time against its physics floor, in one run.

The floor is plain ``mujoco.mj_step`` (C loop, no Python per step) of the same composed models for
the same simulated seconds as the verification (read from the report's ``native_metrics.simulated_s``).
Targets: verification <= 1.5 x floor and < 60 s on a 2-core machine.

    .venv/bin/python benchmarks/f08_verify.py [--quick] [--jobs N] [--dir DIR (default: the materialised reference)]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import mujoco

import rle_design  # noqa: F401 - first: it pins the BLAS kernels before numpy loads
from rle_design.mjcf import load_design
from rle_tasks.core.secrets import load_secret
from rle_tasks.core.solutions import materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f08_mobile_base.public.scene import build_scene
from rle_tasks.f08_mobile_base.verifier import verify


def _floor(directory: Path, sim: dict) -> float:
    design = load_design(directory)
    total = 0.0
    for arm, parts in sim.items():
        jobs = [(kg, False, s) for kg, s in parts["static"].items()]
        jobs += [(2, False, parts["dynamic"])]
        jobs += [(kg, True, s) for kg, s in parts["shelf"].items()]
        for kg, shelf, seconds in jobs:
            sc = build_scene(design.fresh_spec, arm, int(kg), shelf=shelf)
            d = sc.rest_data()
            n = int(round(float(seconds) / sc.model.opt.timestep))
            t0 = time.perf_counter()
            if n:
                mujoco.mj_step(sc.model, d, nstep=n)
            total += time.perf_counter() - t0
    return total


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--dir", default=None, help="artifact directory (default: the shipped reference)")
    p.add_argument("--quick", action="store_true")
    p.add_argument("--jobs", type=int, default=1)
    p.add_argument("--out", default="out/bench/f08_verify.json")
    a = p.parse_args()
    a.dir = a.dir or str(materialise("08-mobile-base", "reference"))
    t0 = time.perf_counter()
    report = verify(Path(a.dir), VerifyContext(secret=load_secret(), quick=a.quick, jobs=a.jobs))
    wall = time.perf_counter() - t0
    sim = report.native_metrics["simulated_s"]
    floor = _floor(Path(a.dir), sim)
    sim_total = sum(sum(v["static"].values()) + v["dynamic"] + sum(v["shelf"].values()) for v in sim.values())
    res = {
        "score": report.score,
        "quick": a.quick,
        "jobs": a.jobs,
        "verify_s": round(wall, 2),
        "floor_s": round(floor, 2),
        "ratio": round(wall / floor, 2) if floor else None,
        "simulated_s": round(sim_total, 1),
        "targets": {"ratio_max": 1.5, "verify_max_s": 60.0},
    }
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(res, indent=2))
    print(json.dumps(res, indent=2))


if __name__ == "__main__":
    main()
