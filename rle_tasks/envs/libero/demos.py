"""Demonstrations of LIBERO-10 from the scripted experts, built by a command and cached outside git.

    python -m rle_tasks.envs.libero.demos [OUT] [--tasks 0 1 ...] [--per-task N] [--seed S] [--views]
        [--view-every K] [--jobs J] [--noise SIGMA]

For each task, the expert runs from LIBERO's official initial states in order (0, 1, ...) until it has
``per_task`` successful episodes or the states run out; only successes are kept. An episode is one
``task<NN>_init<KK>.npz``: ``actions`` (T, 7), ``state`` (T + 1, 8) (the policy's state observation
before each action and after the last), ``sim_states`` (T + 1, n) (the MuJoCo states at the same
instants) and ``language``. With ``--views`` the experts run in a rendering environment and each
episode also stores ``agentview`` and ``wrist``, uint8 (T + 1, 128, 128, 3): the images a policy
would have seen at those instants, which is the dataset a recipe trains on (a policy never sees the
simulator). They are recorded live, not rendered later from ``sim_states``: an observation lags the
stored MuJoCo state by part of a control step (1-2 mm of end-effector motion), so images rendered
from the states differ from what a policy sees in 4-19 % of their pixels. Rendering costs about
0.1 s a step on a CPU against 0.01 s for the simulation, so view datasets are ten times slower to
build; they are cached apart (``<suite>-<seed>-<per_task>-views``). ``--view-every K`` records the
views of every K-th frame only (frames 0, K, 2K, ...; ``view_frames`` lists them and ``agentview``
and ``wrist`` then have one image per listed frame): the steps in between are not rendered, so a
K = 4 dataset costs about a third of a full one (``-views4``).

``manifest.json`` lists every attempt (init state, success, steps), the kept files with their SHA-256,
the per-task success rate of the expert and the build parameters; ``manifest.sha256`` is the digest of
the manifest, so a dataset is identified by one hash. The default location is
``$XDG_CACHE_HOME/rle-bench/libero-demos/<suite>-<seed>-<per_task>`` (``~/.cache`` when unset).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import time
from pathlib import Path

import numpy as np

from rle_tasks.envs.libero import LiberoEnv
from rle_tasks.envs.libero.experts import run_expert, supported

__all__ = ["MAX_FAILURES_IN_A_ROW", "build_demos", "default_dir", "verify_demos"]

MAX_FAILURES_IN_A_ROW = 10
"""A task whose expert fails this many initial states in a row is left (its attempts are listed)."""


def default_dir(
    suite: str, seed: int, per_task: int, views: bool = False, noise: float = 0.0, view_every: int = 1
) -> Path:
    """The cache directory of a dataset built with these parameters."""
    root = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    tag = ("-views" + (str(view_every) if view_every > 1 else "")) if views else ""
    name = f"{suite}-{seed}-{per_task}{tag}{f'-noise{noise:g}' if noise > 0 else ''}"
    return root / "rle-bench" / "libero-demos" / name


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with path.open("rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def build_demos(
    out: Path,
    *,
    suite: str = "libero_10",
    tasks: list[int] | None = None,
    per_task: int = 20,
    seed: int = 0,
    progress=print,
    views: bool = False,
    jobs: int = 1,
    noise: float = 0.0,
    view_every: int = 1,
) -> dict:
    """Build (or complete) the dataset in ``out``; returns the manifest. Episodes already present
    with their recorded checksum are kept, so an interrupted build resumes; ``views`` records both
    camera views of every step (a dataset built otherwise is rebuilt); ``jobs`` builds that many
    tasks at once in worker processes (``rle_tasks.core.runtime.parallel``; each prints its own progress);
    ``noise`` injects N(0, noise) into the executed motion actions (``experts.run_expert``), stores
    the expert's clean actions as ``actions`` and the executed ones as ``executed_actions``;
    ``view_every`` records the views of every K-th frame only."""
    from rle_tasks.core.runtime.parallel import run_parallel

    out.mkdir(parents=True, exist_ok=True)
    old = json.loads((out / "manifest.json").read_text()) if (out / "manifest.json").is_file() else {}
    view_every = max(1, int(view_every)) if views else 1
    if (
        bool(old.get("views")) != views
        or float(old.get("noise", 0.0)) != noise
        or int(old.get("view_every", 1)) != view_every
    ):
        old = {}  # images or not, noise or not, which frames: the other kind of dataset is rebuilt
    ids = list(range(10) if tasks is None else tasks)
    items = [(str(out), suite, t, per_task, seed, views, old, noise, view_every) for t in ids]
    if jobs > 1:
        built = run_parallel(_build_task_item, items, jobs=jobs)
    else:
        built = [_build_task(*item, progress=progress) for item in items]
    files: dict[str, str] = {}
    report: dict[str, dict] = {}
    for task_id, (entry, kept_files) in zip(ids, built, strict=True):
        report[str(task_id)] = entry
        files.update(kept_files)
    manifest = {
        "suite": suite,
        "seed": seed,
        "per_task": per_task,
        "tasks": report,
        "files": dict(sorted(files.items())),
        "views": views,
        **({"view_every": view_every} if view_every > 1 else {}),
        **({"noise": noise} if noise > 0 else {}),
    }
    text = json.dumps(manifest, indent=1, sort_keys=True)
    (out / "manifest.json").write_text(text)
    (out / "manifest.sha256").write_text(hashlib.sha256(text.encode()).hexdigest() + "\n")
    return manifest


def _build_task_item(item: tuple) -> tuple[dict, dict[str, str]]:
    return _build_task(*item, progress=lambda line: print(line, flush=True))


def _build_task(
    out_dir: str,
    suite: str,
    task_id: int,
    per_task: int,
    seed: int,
    views: bool,
    old: dict,
    noise: float = 0.0,
    view_every: int = 1,
    progress=print,
) -> tuple[dict, dict[str, str]]:
    """One task's episodes: ``(manifest entry, {file: sha256})``."""
    out = Path(out_dir)
    done = _complete(out, old, task_id, per_task)
    if done is not None:  # every episode of this task is present and intact: nothing to simulate
        progress(f"task {task_id}: {done[0]['kept']} episodes already built")
        return done
    files: dict[str, str] = {}
    with LiberoEnv(suite, task_id, render=views) as env:
        task = env.start()
        scene = env.scene()
        goal = scene["goal"]
        entry = {
            "name": task.name,
            "language": task.language,
            "goal": goal,
            "n_init_states": task.n_init_states,
            "attempts": [],
        }
        if not supported(scene):
            entry["skipped"] = "no expert skill for every predicate of the goal"
            progress(f"task {task_id}: skipped ({entry['skipped']}: {goal})")
            return entry, files
        kept, failures = 0, 0
        for init in range(task.n_init_states):
            if kept >= per_task:
                break
            if failures >= MAX_FAILURES_IN_A_ROW:
                entry["stopped"] = f"{failures} failures in a row"
                progress(f"task {task_id}: stopped after {failures} failures in a row")
                break
            name = f"task{task_id:02d}_init{init:02d}.npz"
            prior = old.get("files", {}).get(name)
            if prior and (out / name).is_file() and _sha256(out / name) == prior:
                files[name] = prior
                kept += 1
                entry["attempts"].append({"init": init, "success": True, "cached": True})
                continue
            t0 = time.perf_counter()
            res = run_expert(
                env,
                init,
                np.random.default_rng([seed, task_id, init]),
                record=True,
                noise=noise,
                view_every=view_every,
            )
            entry["attempts"].append({"init": init, "success": res.success, "steps": res.steps})
            progress(
                f"task {task_id} init {init}: {'success' if res.success else 'failure'} in {res.steps} steps "
                f"({time.perf_counter() - t0:.1f} s); kept {kept + res.success}/{per_task}"
            )
            if not res.success:
                failures += 1
                continue
            failures = 0
            np.savez_compressed(
                out / name,
                actions=res.actions.astype(np.float32),
                state=res.observations.astype(np.float32),
                sim_states=res.sim_states,
                language=np.array(task.language),
                **(res.views or {}),
                **({} if res.view_frames is None else {"view_frames": res.view_frames}),
                **({} if res.executed is None else {"executed_actions": res.executed.astype(np.float32)}),
            )
            files[name] = _sha256(out / name)
            kept += 1
        tried = entry["attempts"]
        entry["expert_success_rate"] = sum(a["success"] for a in tried) / max(1, len(tried))
        entry["kept"] = kept
    return entry, files


def _complete(out: Path, old: dict, task_id: int, per_task: int) -> tuple[dict, dict] | None:
    """(task entry, files) of a task the previous build completed, when all its files are intact. A
    task is complete when it has ``per_task`` episodes, or when its expert was tried from every
    official initial state (LIBERO ships 50 a task), or was stopped by failures in a row: another
    build would run the same seeded failures again."""
    entry = old.get("tasks", {}).get(str(task_id))
    if not entry or old.get("per_task") != per_task:
        return None
    tried_all = len(entry.get("attempts", ())) >= entry.get("n_init_states", 50) or "stopped" in entry
    if entry.get("kept", 0) < per_task and not tried_all:
        return None
    prefix = f"task{task_id:02d}_"
    mine = {n: h for n, h in old.get("files", {}).items() if n.startswith(prefix)}
    if len(mine) != entry["kept"] or any(
        not (out / n).is_file() or _sha256(out / n) != h for n, h in mine.items()
    ):
        return None
    return entry, mine


def verify_demos(out: Path) -> list[str]:
    """Problems of a built dataset: a manifest that does not match its digest, missing or altered
    episode files (empty when the dataset is intact)."""
    problems = []
    text = (out / "manifest.json").read_text()
    if hashlib.sha256(text.encode()).hexdigest() != (out / "manifest.sha256").read_text().strip():
        problems.append("manifest.json does not match manifest.sha256")
    for name, digest in json.loads(text)["files"].items():
        path = out / name
        if not path.is_file():
            problems.append(f"{name} is missing")
        elif _sha256(path) != digest:
            problems.append(f"{name} was altered")
    return problems


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out", nargs="?", help="dataset directory (default: the cache directory)")
    p.add_argument("--suite", default="libero_10")
    p.add_argument("--tasks", type=int, nargs="*", help="task indices (default: all ten)")
    p.add_argument("--per-task", type=int, default=20, help="successful demonstrations per task")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--views", action="store_true", help="record both 128 px views of every step")
    p.add_argument("--view-every", type=int, default=1, help="with --views: record every K-th frame's views")
    p.add_argument("--jobs", type=int, default=1, help="tasks built at once (worker processes)")
    p.add_argument(
        "--noise",
        type=float,
        default=0.0,
        help="DART: N(0, noise) added to executed motion actions [action units]",
    )
    a = p.parse_args(argv)
    if a.view_every < 1:
        p.error("--view-every must be at least 1")
    out = Path(a.out) if a.out else default_dir(a.suite, a.seed, a.per_task, a.views, a.noise, a.view_every)
    if not (out / "manifest.sha256").is_file():
        print(
            f"first use: building the LIBERO demonstrations into {out} (the full dataset took 60 min with two "
            "jobs on the 2-core machine); an interrupted build resumes, later runs reuse it",
            flush=True,
        )
    manifest = build_demos(
        out,
        suite=a.suite,
        tasks=a.tasks,
        per_task=a.per_task,
        seed=a.seed,
        views=a.views,
        jobs=a.jobs,
        noise=a.noise,
        view_every=a.view_every,
    )
    for tid, e in manifest["tasks"].items():
        if "skipped" in e:
            print(f"task {tid}: {e['skipped']}")
        else:
            print(f"task {tid}: {e['kept']} kept, expert success {e['expert_success_rate']:.0%}")
    digest = (out / "manifest.sha256").read_text().strip()
    print(f"{out}: {len(manifest['files'])} episodes, manifest {digest}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
