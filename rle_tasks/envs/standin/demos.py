"""Demonstrations of the bimanual stand-in from its scripted experts, built by a command and cached
outside git.

    python -m rle_tasks.envs.standin.demos [OUT] [--per-task N] [--jobs J] [--noise SIGMA]

For each task the expert runs from the layouts of seeds 0, 1, ... (the demonstration range; every
evaluation layout comes from a disjoint range) until it has ``per_task`` successful episodes; only
successes are kept. An episode is one ``task<N>_seed<KKK>.npz``: ``actions`` (T, 14) float32,
``state`` (T + 1, 16) float32 (before each action and after the last), ``head`` and ``front`` uint8
(T + 1, 128, 128, 3) (the views a policy sees at those instants) and ``language``. With ``--noise``
each executed action has N(0, SIGMA) [rad] added to its joint targets while the stored action stays
the expert's (demonstrations that show recoveries).

``manifest.json`` lists every attempt (seed, success, steps), the kept files with their SHA-256 and
the build parameters; ``manifest.sha256`` is its digest, so a dataset is identified by one hash.
The default location is ``$XDG_CACHE_HOME/rle-bench/standin-demos/<per_task>[-noise<S>]``.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import time
from pathlib import Path

import numpy as np

from rle_tasks.envs.standin.env import StandinEnv
from rle_tasks.envs.standin.experts import Expert
from rle_tasks.envs.standin.tasks import TASKS

__all__ = ["build_demos", "default_dir", "record"]

MAX_FAILURES_IN_A_ROW = 10
"""A task whose expert fails this many layouts in a row stops the build (the manifest says so)."""


def default_dir(per_task: int, noise: float = 0.0) -> Path:
    root = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return root / "rle-bench" / "standin-demos" / f"{per_task}{f'-noise{noise:g}' if noise > 0 else ''}"


def record(env: StandinEnv, seed: int, noise: float = 0.0) -> tuple[bool, dict[str, np.ndarray]]:
    """Run the expert from the layout of ``seed``; (success, the episode's arrays)."""
    rng = np.random.default_rng([env.task_index, seed, 7])
    obs = env.reset(seed)
    expert = Expert(env)
    rec: dict[str, list] = {
        "actions": [],
        "state": [obs["state"]],
        "head": [obs["head"]],
        "front": [obs["front"]],
    }
    ok = False
    while not expert.done:
        a = expert.act()
        rec["actions"].append(a)
        run = a.copy()
        if noise > 0:
            run[[0, 1, 2, 3, 4, 5, 7, 8, 9, 10, 11, 12]] += rng.normal(0.0, noise, 12)
        ok = env.step(run) or ok
        obs = env.observe(views=True)
        for k in ("state", "head", "front"):
            rec[k].append(obs[k])
    out = {k: np.asarray(v) for k, v in rec.items()}
    out["actions"] = out["actions"].astype(np.float32)
    out["state"] = out["state"].astype(np.float32)
    return ok, out


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _build_task(item: tuple) -> dict:
    out, task, per_task, noise = item
    import rle_design  # noqa: F401  (rendering backend before MuJoCo)

    env = StandinEnv(task)
    attempts, files, fails, seed = [], {}, 0, 0
    while len(files) < per_task and fails < MAX_FAILURES_IN_A_ROW:
        ok, rec = record(env, seed, noise)
        attempts.append({"seed": seed, "success": ok, "steps": len(rec["actions"])})
        if ok:
            fails = 0
            name = f"task{task}_seed{seed:03d}.npz"
            np.savez_compressed(Path(out) / name, language=np.array(TASKS[task].instruction), **rec)
            files[name] = _sha256(Path(out) / name)
        else:
            fails += 1
        seed += 1
    return {"task": task, "attempts": attempts, "files": files}


def build_demos(out: Path, per_task: int = 50, jobs: int = 1, noise: float = 0.0, tasks=None) -> Path:
    """Build the dataset into ``out`` (created); returns ``out``. Progress goes to stdout."""
    from rle_tasks.core.runtime.parallel import run_parallel

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    tasks = list(range(len(TASKS))) if tasks is None else list(tasks)
    t0 = time.monotonic()
    results = run_parallel(_build_task, [(str(out), t, per_task, noise) for t in tasks], jobs=jobs)
    manifest = {
        "environment": "bimanual stand-in for RoboTwin 2.0",
        "per_task": per_task,
        "noise": noise,
        "tasks": {str(r["task"]): {"instruction": TASKS[r["task"]].instruction, **r} for r in results},
    }
    text = json.dumps(manifest, indent=1, sort_keys=True)
    (out / "manifest.json").write_text(text)
    (out / "manifest.sha256").write_text(hashlib.sha256(text.encode()).hexdigest() + "\n")
    for r in results:
        ok = sum(a["success"] for a in r["attempts"])
        print(f"task {r['task']} ({TASKS[r['task']].name}): {ok}/{len(r['attempts'])} expert successes kept")
    print(f"built {out} in {time.monotonic() - t0:.0f} s")
    return out


def verify_demos(out: Path) -> list[str]:
    """Files whose SHA-256 differs from the manifest's (empty: the dataset is intact)."""
    manifest = json.loads((Path(out) / "manifest.json").read_text())
    bad = []
    for r in manifest["tasks"].values():
        for name, digest in r["files"].items():
            p = Path(out) / name
            if not p.is_file() or _sha256(p) != digest:
                bad.append(name)
    return bad


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m rle_tasks.envs.standin.demos", description=__doc__.split("\n")[0]
    )
    ap.add_argument("out", nargs="?", type=Path)
    ap.add_argument("--per-task", type=int, default=50)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--noise", type=float, default=0.0)
    ap.add_argument("--tasks", type=int, nargs="*")
    args = ap.parse_args(argv)
    out = args.out or default_dir(args.per_task, args.noise)
    if args.tasks is None and up_to_date(out, args.per_task, args.noise):
        print(f"{out} is built and intact (manifest {(out / 'manifest.sha256').read_text().strip()[:12]})")
        return 0
    print(
        f"first use: building the stand-in demonstrations ({args.per_task} per task) into {out}; about 10 s of "
        "one core per episode (612 s with two jobs on an idle 2-core machine, 1,295 s on a loaded one); "
        "later runs reuse it",
        flush=True,
    )
    build_demos(out, args.per_task, args.jobs, args.noise, args.tasks)
    return 0


def up_to_date(out: Path, per_task: int, noise: float) -> bool:
    """A complete dataset with these parameters is at ``out`` and every file matches the manifest."""
    path = Path(out) / "manifest.json"
    if not path.is_file() or not (Path(out) / "manifest.sha256").is_file():
        return False
    manifest = json.loads(path.read_text())
    if manifest.get("per_task") != per_task or manifest.get("noise") != noise:
        return False
    if len(manifest.get("tasks", {})) != len(TASKS):
        return False
    return not verify_demos(out)


if __name__ == "__main__":
    raise SystemExit(main())
