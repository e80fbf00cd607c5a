"""Family 08: full verification time against its physics, in one run.

Three measures of the same verification (``rle verify 08-mobile-base`` on the shipped reference):

* ``physics_s``: the time spent inside ``mujoco.mj_step`` during the verification itself (every call
  timed in this process; one worker only). This is the physics floor: the verification steps one
  physics step at a time where a term is due every step (shelf contacts, the batteries' arm hold).
* ``controller_cpu_s``: CPU time of the sandboxed controller processes (the submission's own
  computation: its imports, its model, its IK plans and its control law) less the time they polled
  after ``Sandbox.wake`` (``controller_wake_poll_s``, the platform's), one worker only.
* ``replay_floor_s``: plain ``mj_step`` (C loop) of freshly composed scenes, uncontrolled, for the
  same simulated seconds as the report's ``native_metrics.simulated_s``. An uncontrolled arm
  collapses into heavier contact states, so this overstates the verification's physics (the first
  measure is the exact one); kept for comparison with earlier measurements.

Targets (one worker): (verification - controller CPU) / physics <= 1.5, the platform's own cost over
the physics it must do (as ``f07_verify`` excludes its policy's compute), and verification < 60 s.
``--repeats N`` reports the best of N runs (on a shared virtual machine the same run varies by ~5 %).

    .venv/bin/python -m benchmarks f08_verify [--quick] [--jobs N] [--repeats N] [--dir DIR (default: the reference)]
"""

from __future__ import annotations

import argparse
import json
import resource
import time
from pathlib import Path

import mujoco

from rle_design.mjcf import load_design
from rle_design.sandbox import wake_poll_total_s
from rle_tasks.core.runtime.secrets import load_secret
from rle_tasks.core.solutions import materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f08_mobile_base.public.scene import build_scene
from rle_tasks.f08_mobile_base.verifier import verify

TARGET_RATIO, TARGET_S = 1.5, 60.0


class _PhysicsClock:
    """Wraps ``mujoco.mj_step`` in this process and sums the seconds spent inside it."""

    def __init__(self) -> None:
        self.seconds, self.steps, self._step = 0.0, 0, mujoco.mj_step

    def __enter__(self) -> _PhysicsClock:
        step, clock = self._step, time.perf_counter

        def timed(m: mujoco.MjModel, d: mujoco.MjData, nstep: int = 1) -> None:
            t0 = clock()
            step(m, d, nstep)
            self.seconds += clock() - t0
            self.steps += nstep

        mujoco.mj_step = timed
        return self

    def __exit__(self, *exc: object) -> None:
        mujoco.mj_step = self._step


def _children_cpu() -> float:
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def _replay_floor(directory: Path, sim: dict) -> float:
    design = load_design(directory)
    total = 0.0
    for arm, parts in sim.items():
        jobs = [(kg, False, s) for kg, s in parts["static"].items()]
        jobs += [(2, False, parts["dynamic"])]
        jobs += [(kg, True, s) for kg, s in parts["shelf"].items()]
        for kg, shelf, seconds in jobs:
            sc = build_scene(design.fresh_spec, arm, int(kg), shelf=shelf, visual=False)
            d = sc.rest_data()
            n = int(round(float(seconds) / sc.model.opt.timestep))
            t0 = time.perf_counter()
            if n:
                mujoco.mj_step(sc.model, d, nstep=n)
            total += time.perf_counter() - t0
    return total


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--dir", default=None, help="artifact directory (default: the shipped reference)")
    p.add_argument("--quick", action="store_true")
    p.add_argument("--jobs", type=int, default=1)
    p.add_argument("--repeats", type=int, default=1, help="runs; the best one is reported")
    p.add_argument("--out", default="out/bench/f08_verify.json")
    a = p.parse_args()
    a.dir = a.dir or str(materialise("08-mobile-base", "reference"))
    runs = []
    for _ in range(a.repeats):
        cpu0, poll0 = _children_cpu(), wake_poll_total_s()
        with _PhysicsClock() as clock:
            t0 = time.perf_counter()
            report = verify(Path(a.dir), VerifyContext(secret=load_secret(), quick=a.quick, jobs=a.jobs))
            wall = time.perf_counter() - t0
        # the controllers' polls after wake() are the platform's, not the submission's computation
        polled = wake_poll_total_s() - poll0
        runs.append((wall, _children_cpu() - cpu0 - polled, clock, polled))
    # best run: interference from the rest of the machine only ever adds time
    wall, controller, clock, polled = min(
        runs, key=lambda r: (r[0] - r[1]) / r[2].seconds if a.jobs == 1 else r[0]
    )
    sim = report.native_metrics["simulated_s"]
    floor = _replay_floor(Path(a.dir), sim)
    sim_total = sum(sum(v["static"].values()) + v["dynamic"] + sum(v["shelf"].values()) for v in sim.values())
    res = {
        "score": report.score,
        "quick": a.quick,
        "jobs": a.jobs,
        "runs": [round(r[0], 2) for r in runs],
        "verify_s": round(wall, 2),
        "simulated_s": round(sim_total, 1),
        "replay_floor_s": round(floor, 2),
        "ratio_to_replay_floor": round(wall / floor, 2) if floor else None,
    }
    ok = wall < TARGET_S
    if a.jobs == 1:  # workers' physics and controllers are not visible from here
        res |= {
            "physics_s": round(clock.seconds, 2),
            "physics_steps": clock.steps,
            "controller_cpu_s": round(controller, 2),
            "controller_wake_poll_s": round(polled, 2),
            "platform_s": round(wall - controller - clock.seconds, 2),
            "ratio_to_physics": round(wall / clock.seconds, 2),
            "ratio_minus_controller_to_physics": round((wall - controller) / clock.seconds, 3),
        }
        ok = ok and res["ratio_minus_controller_to_physics"] <= TARGET_RATIO
    res["targets"] = {"ratio_minus_controller_to_physics_max": TARGET_RATIO, "verify_max_s": TARGET_S}
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(res, indent=2))
    print(json.dumps(res, indent=2))
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
