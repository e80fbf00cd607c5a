"""The shared rollout loop with a sandboxed 50 Hz controller against raw ``mj_step`` of the same scene.

Scene: the shipped ``08-mobile-base`` reference base with a Panda, the 1 kg payload and the shelf
(timestep 2 ms, so 10 physics steps per control period). Three timings of the same simulated time:

* raw: ``mujoco.mj_step(model, data, nstep=N)`` (the physics floor);
* rollout: ``run_episode`` calling a sandboxed controller (``controller.py`` returning its ``ctrl``
  input, one sandbox round trip per period) and stepping in C between calls, waking the controller
  one physics step ahead of each call (``prepare=box.wake``; its polls are its own CPU, reported);
* rollout with an in-process controller: the loop's own cost, without the sandbox round trip;
* rollout + trial terms: the same with the shelf trial's terms (wheel loads every 5 steps, contact,
  tilt, support loss and hold checks every period), for information.

Target: rollout <= 1.3 x raw.

    .venv/bin/python -m benchmarks rollout_overhead [--seconds 8] [--repeats 3]
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np

from rle_design.mjcf import load_design
from rle_design.rollout import run_episode
from rle_design.sandbox import Sandbox, SandboxLimits, wake_poll_for
from rle_tasks.core.solutions import materialise
from rle_tasks.f08_mobile_base.env import trial_terms
from rle_tasks.f08_mobile_base.public.scene import build_scene

CONTROLLER = """
def control(t, qpos, qvel, ctrl):
    return ctrl
"""
TARGET = 1.3


def _scene():
    design = load_design(materialise("08-mobile-base", "reference"))
    return build_scene(design.fresh_spec, "panda", 1, shelf=True)


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--seconds", type=float, default=8.0, help="simulated time per timing [s]")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--out", default="out/bench/rollout_overhead.json")
    a = p.parse_args()
    scene = _scene()
    m = scene.model
    n_sub = int(round(0.02 / m.opt.timestep))
    n = int(round(a.seconds / m.opt.timestep)) // n_sub * n_sub
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "controller.py"
        path.write_text(CONTROLLER)
        limits = SandboxLimits(call_timeout_s=30.0, cpu_seconds=600.0, wake_poll_s=wake_poll_for(1))
        box = Sandbox(str(path), limits=limits)
        box.start()

        calls = [0]

        def control(model: mujoco.MjModel, d: mujoco.MjData, t: float) -> None:
            calls[0] += 1
            cmd = box.call("control", float(d.time), d.qpos, d.qvel, d.ctrl, shape=(m.nu,), finite=True)
            d.ctrl[:] = np.asarray(cmd, dtype=float)

        def local(model: mujoco.MjModel, d: mujoco.MjData, t: float) -> None:
            d.ctrl[:] = np.asarray(d.ctrl.copy(), dtype=float)

        raw, loop, terms, inproc = [], [], [], []
        for _ in range(a.repeats):
            d = scene.rest_data()
            t0 = time.perf_counter()
            mujoco.mj_step(m, d, nstep=n)
            raw.append(time.perf_counter() - t0)
            d = scene.rest_data()
            t0 = time.perf_counter()
            run_episode(m, d, n, control=control, control_every=n_sub, prepare=box.wake)
            loop.append(time.perf_counter() - t0)
            d = scene.rest_data()
            t0 = time.perf_counter()
            run_episode(m, d, n, control=local, control_every=n_sub)
            inproc.append(time.perf_counter() - t0)
            d = scene.rest_data()
            _, tt = trial_terms(scene, d.site_xpos[scene.tool_site] + 10.0)
            t0 = time.perf_counter()
            run_episode(m, d, n, control=control, control_every=n_sub, terms=tt, prepare=box.wake)
            terms.append(time.perf_counter() - t0)
        box.close()
    res = {
        "simulated_s": n * m.opt.timestep,
        "raw_s": round(min(raw), 4),
        "rollout_s": round(min(loop), 4),
        "rollout_terms_s": round(min(terms), 4),
        "rollout_in_process_s": round(min(inproc), 4),
        "ratio": round(min(loop) / min(raw), 3),
        "ratio_with_terms": round(min(terms) / min(raw), 3),
        "ratio_in_process_controller": round(min(inproc) / min(raw), 3),
        "per_call_overhead_ms": round(1000 * (min(loop) - min(raw)) / (n // n_sub), 4),
        "wake_poll_s": limits.wake_poll_s,
        "child_wake_poll_ms_per_call": round(1000 * box.wake_poll_s / max(1, calls[0]), 4),
        "target_ratio_max": TARGET,
    }
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(res, indent=2))
    print(json.dumps(res, indent=2))
    return 0 if res["ratio"] <= TARGET else 1
