"""Batched gravity-map throughput on the 7-joint Panda GELLO leader (target: >= 400k poses/s).

Usage: ``.venv/bin/python -m benchmarks f09_gravity_map [--poses N] [--repeat R]``. Prints poses/s of
``rle_design.kinematics.GravityMap`` (closed-form numpy over a batch), of a Python loop over
``pinocchio.computeGeneralizedGravity`` for comparison, and the largest disagreement between the two.
Exit status 1 if the batched map misses 400k poses/s.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np
import pinocchio as pin

TARGET = 400_000.0


def main() -> int:
    from rle_design.kinematics import GravityMap, model_from_mujoco
    from rle_tasks.f09_gello.device import stock_model
    from rle_tasks.f09_gello.public.gello_helpers import workspace_grid

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--poses", type=int, default=200_000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(sys.argv[1:])
    m = stock_model("panda")
    km = model_from_mujoco(m)
    gmap = GravityMap(km)
    q = workspace_grid(m.jnt_range, args.poses, seed=0)
    gmap(q[:1000])  # warm-up
    best = min(_timed(lambda: gmap(q)) for _ in range(args.repeat))
    rate = args.poses / best
    n_ref = min(args.poses, 20_000)
    t0 = time.perf_counter()
    ref = np.array([pin.computeGeneralizedGravity(km.model, km.data, p) for p in q[:n_ref]])
    ref_rate = n_ref / (time.perf_counter() - t0)
    err = float(np.max(np.abs(gmap(q[:n_ref]) - ref)))
    print(f"GravityMap (numpy, batch {args.poses}): {rate:,.0f} poses/s (target {TARGET:,.0f})")
    print(f"pinocchio.computeGeneralizedGravity loop: {ref_rate:,.0f} poses/s")
    print(f"max |GravityMap - pinocchio| over {n_ref} poses: {err:.2e} N m")
    return 0 if rate >= TARGET and err < 1e-9 else 1


def _timed(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


if __name__ == "__main__":
    raise SystemExit(main())
