"""Physics steps per second of the bare pocket cube (no robot), with and without its detent.

Usage: ``.venv/bin/python benchmarks/cube_step_rate.py [--steps N] [--turns N]``. Prints one line per
configuration:

- ``mj_step only``: the free cube resting on a floor, MuJoCo alone (no detent: the mechanism's floor);
- ``resting, detent``: the same with the detent applied every step (``scripted.step``);
- ``turning, detent``: scripted quarter turns (core fixed, gravity on), the detent and the turn driver;
- ``two arms``: the ``03-pocket-cube`` environment (``cube.env.CubeEnv``, both Pandas under their
  operational-space controllers, the cube on its stand, detent every step), stepped by 14-D actions
  (arms holding, no rendering), with and without the detent (``TabletopEnv.substep`` bypassed).

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


def two_arms(actions: int, *, detent: bool) -> float:
    """Physics steps/s of the two-arm cube environment stepped by holding 14-D actions."""
    from rle_design.control import TabletopEnv
    from rle_tasks.f03_physical_reasoning.cube.env import make_env
    from rle_tasks.f03_physical_reasoning.cube.scene import PUBLIC_SCRAMBLES, CubeInstance

    env = make_env(CubeInstance.from_moves(PUBLIC_SCRAMBLES[0]), image_size=None)
    model = env.build()
    env.prepare(model)
    data = mujoco.MjData(model)
    env.reset(model, data)
    hold = np.zeros(14)
    hold[[6, 13]] = -1.0
    if not detent:  # same controller loop, the cube's mechanism left out
        object.__setattr__(env, "substep", lambda model, data, k: TabletopEnv.substep(env, model, data, k))
    t0 = time.perf_counter()
    for _ in range(actions):
        env.step(model, data, hold)
    return actions * env.n_substeps / (time.perf_counter() - t0)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=5000)
    p.add_argument("--turns", type=int, default=20)
    p.add_argument("--actions", type=int, default=200, help="actions of the two-arm runs (25 steps each)")
    args = p.parse_args()
    bare = resting(args.steps, detent=False)
    rest = resting(args.steps, detent=True)
    turn, worst = turning(args.turns)
    print(f"mj_step only (resting)   {bare:8.0f} steps/s")
    print(f"resting, detent          {rest:8.0f} steps/s")
    print(
        f"turning, detent          {turn:8.0f} steps/s  ({args.turns} quarter turns, worst {worst:.2f} deg)"
    )
    arms_bare = two_arms(args.actions, detent=False)
    arms = two_arms(args.actions, detent=True)
    print(f"two arms, no detent       {arms_bare:8.0f} steps/s  ({args.actions} actions of 25 steps)")
    print(f"two arms, detent          {arms:8.0f} steps/s  ({arms / 25:.0f} actions/s)")
    return 0 if min(rest, turn) >= TARGET else 1


if __name__ == "__main__":
    sys.exit(main())
