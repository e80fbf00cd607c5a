"""Physics steps per second of the bare pocket cube (no robot), with and without its detent.

Usage: ``.venv/bin/python benchmarks/cube_step_rate.py [--steps N] [--turns N]``. Prints one line per
configuration:

- ``mj_step only``: the free cube resting on a floor, MuJoCo alone (no detent: the mechanism's floor);
- ``resting, detent``: the same with the detent applied every step (``scripted.step``);
- ``turning, detent``: scripted quarter turns (core fixed, gravity on), the detent and the turn driver.

Exit status 1 when the cube with its detent runs below 1000 steps/s (a 50,000-step budget would then
take over 50 s of physics alone). Measured numbers go in ``rle_tasks/f03_physical_reasoning/cube/README.md``.
"""

from __future__ import annotations

import argparse
import sys
import time

import mujoco
import numpy as np

from rle_tasks.f03_physical_reasoning.cube.detent import CubeDetent
from rle_tasks.f03_physical_reasoning.cube.lattice import MOVES
from rle_tasks.f03_physical_reasoning.cube.model import CubeConfig, cube_spec
from rle_tasks.f03_physical_reasoning.cube.scripted import scripted_turn, step

TARGET = 1000.0


def resting(steps: int, *, detent: bool) -> float:
    """Steps/s of a free cube resting on the floor."""
    model = cube_spec(CubeConfig(pos=(0.0, 0.0, 0.0325))).compile()
    data = mujoco.MjData(model)
    det = CubeDetent(model)
    step(model, data, det, 200)  # settle
    t0 = time.perf_counter()
    if detent:
        step(model, data, det, steps)
    else:
        for _ in range(steps):
            mujoco.mj_step(model, data)
    return steps / (time.perf_counter() - t0)


def turning(turns: int) -> tuple[float, float]:
    """Steps/s and worst settled misalignment [deg] over random scripted quarter turns."""
    model = cube_spec(CubeConfig(free=False, pos=(0.0, 0.0, 0.2)), floor=False).compile()
    data = mujoco.MjData(model)
    det = CubeDetent(model)
    step(model, data, det, 100)
    rng = np.random.default_rng(0)
    total, worst = 0, 0.0
    t0 = time.perf_counter()
    for i in rng.integers(0, len(MOVES), turns):
        result = scripted_turn(model, data, det, MOVES[i])
        total += result.total_steps
        worst = max(worst, float(np.degrees(result.reading.misalignment)))
    return total / (time.perf_counter() - t0), worst


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=5000)
    p.add_argument("--turns", type=int, default=20)
    args = p.parse_args()
    bare = resting(args.steps, detent=False)
    rest = resting(args.steps, detent=True)
    turn, worst = turning(args.turns)
    print(f"mj_step only (resting)   {bare:8.0f} steps/s")
    print(f"resting, detent          {rest:8.0f} steps/s")
    print(
        f"turning, detent          {turn:8.0f} steps/s  ({args.turns} quarter turns, worst {worst:.2f} deg)"
    )
    return 0 if min(rest, turn) >= TARGET else 1


if __name__ == "__main__":
    sys.exit(main())
