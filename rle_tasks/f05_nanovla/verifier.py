"""Replay verifier of ``05-libero-open``: retrain the submitted recipe offline, serve it, run the episodes.

1. The artifact contract (``envs.libero.replay.check_solution``): one regular UTF-8 ``solution.py`` of
   at most 1 MiB.
2. Training runs once, alone in the project sandbox, in a fresh directory holding only
   ``solution.py`` and a read-only copy of the demonstrations (``dataset_dir``), within the card's
   1,800 s plus 120 s; it must write a non-empty ``ckpt.pt`` (``meta.json`` optional).
3. The episode set: LIBERO-10's official initial states, 10 tasks x 50 = 500 episodes. Episodes are
   independent units for the core runner (``run_parallel``, ``--jobs``, Ray): each unit serves the
   trained checkpoint in its own sandboxed process and runs up to ``UNIT_EPISODES`` episodes of one
   task. Units carry the recipe and its checkpoint as bytes, so Ray workers need no shared disk.
4. The score: successes over the set; zero when step 1 or 2 fails (``replay_failed``) or fewer than
   475 episodes complete (``incomplete``; an episode ended by a fault of the served policy is not
   complete). ``--episodes N`` (and ``--quick``, ``QUICK_EPISODES``) runs the first N episodes of an
   order derived from the secret (tasks interleaved, so N = 20 is two episodes of each task); such a
   report is marked ``partial`` and scores successes over the episodes it ran.

The served policy never sees the simulator, the secret or the episode order: a request carries the
instruction, the two 128 x 128 views and the 8-D state (``rle_design.policy_socket``).
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np

from rle_design.policy_socket import ProtocolError
from rle_tasks.core.report import ErrorEntry, VerifierReport
from rle_tasks.core.runner import run_parallel
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.secrets import derive_rng
from rle_tasks.core.task import VerifyContext
from rle_tasks.core.verify import VerifierSetupError
from rle_tasks.f05_nanovla.scoring import TASK_ID, required_complete, rubric

SUITE = "libero_10"
N_TASKS = 10
INITS_PER_TASK = 50
"""LIBERO's official initial states per task."""
QUICK_EPISODES = 2
"""Episodes of a quick (partial) verification: ``make demo`` and the golden table."""
UNIT_EPISODES = 5
"""Episodes of one task in one runner unit (one served process, one simulator)."""
DATASET_ENV = "RLE_F05_DEMOS"
"""Names a demonstration dataset directory other than the default (tests, operators)."""
DATASET_SEED = 0
DATASET_PER_TASK = 50
"""Expert demonstrations per LIBERO-10 task in the training dataset (LIBERO ships 50 per task)."""


def episode_set() -> list[tuple[int, int]]:
    """The fixed episode set: every (task, official initial state) of LIBERO-10, 500 pairs."""
    return [(t, i) for t in range(N_TASKS) for i in range(INITS_PER_TASK)]


def episode_order(ctx: VerifyContext) -> list[tuple[int, int]]:
    """The episode set in the order a partial run takes it: tasks interleaved in a secret-derived
    order, each task's initial states in a secret-derived permutation."""
    rng = derive_rng(ctx.secret, TASK_ID, "episodes")
    tasks = [int(t) for t in rng.permutation(N_TASKS)]
    inits = {t: [int(i) for i in rng.permutation(INITS_PER_TASK)] for t in range(N_TASKS)}
    return [(t, inits[t][k]) for k in range(INITS_PER_TASK) for t in tasks]


def dataset_dir() -> Path:
    """The demonstrations the recipe trains on (``RLE_F05_DEMOS`` or the default cache)."""
    from rle_tasks.envs.libero.demos import default_dir

    given = os.environ.get(DATASET_ENV)
    return Path(given) if given else default_dir(SUITE, DATASET_SEED, DATASET_PER_TASK, views=True)


def _dataset(path: Path) -> str:
    """The dataset's manifest digest; ``VerifierSetupError`` when it is not built."""
    digest = path / "manifest.sha256"
    if not digest.is_file():
        raise VerifierSetupError(
            f"the demonstration dataset is not built at {path}: build it with `make libero-demos` "
            f"(or point {DATASET_ENV} at a dataset built by `python -m rle_tasks.envs.libero.demos`)",
            code="f05.no_dataset",
        )
    return digest.read_text().strip()


def run_unit(item: tuple) -> list[dict]:
    """Serve the trained recipe and run one task's episodes (a runner unit; picklable).

    Args:
        item: ``(solution bytes, ckpt bytes, meta bytes or None, suite, task, inits, first episode
            number, horizon override or None)``.
    """
    from rle_tasks.envs.libero import LiberoEnv
    from rle_tasks.envs.libero.client import run_episode, serving
    from rle_tasks.envs.libero.replay import CKPT, SOLUTION

    solution, ckpt, meta, suite, task, inits, first, max_steps = item
    stage = Path(tempfile.mkdtemp(prefix="rle-f05u-"))
    os.chmod(stage, 0o755)
    out: list[dict] = []
    try:
        (stage / SOLUTION).write_bytes(solution)
        (stage / CKPT).write_bytes(ckpt)
        if meta is not None:
            (stage / "meta.json").write_bytes(meta)
        try:
            with serving(stage) as policy, LiberoEnv(suite, task) as env:
                for k, init in enumerate(inits):
                    res = run_episode(env, policy, init, episode=first + k, max_steps=max_steps)
                    out.append({"task": task, **dataclasses.asdict(res)})
        except ProtocolError as exc:  # the policy never connected: the unit's episodes did not run
            done = {r["init_index"] for r in out}
            out += [
                {
                    "task": task,
                    "init_index": i,
                    "success": False,
                    "steps": 0,
                    "requests": 0,
                    "fault": exc.code,
                }
                for i in inits
                if i not in done
            ]
            out[-1]["message"] = exc.message
        return out
    finally:
        shutil.rmtree(stage, ignore_errors=True)


def units(
    episodes: list[tuple[int, int]], solution: bytes, ckpt: bytes, meta: bytes | None, max_steps: int | None
) -> list[tuple]:
    """Runner units: the episodes grouped by task, ``UNIT_EPISODES`` at most per unit."""
    by_task: dict[int, list[tuple[int, int]]] = {}
    for k, (t, i) in enumerate(episodes):
        by_task.setdefault(t, []).append((k, i))
    items = []
    for t, eps in sorted(by_task.items()):
        for s in range(0, len(eps), UNIT_EPISODES):
            chunk = eps[s : s + UNIT_EPISODES]
            inits = tuple(i for _, i in chunk)
            items.append((solution, ckpt, meta, SUITE, t, inits, chunk[0][0], max_steps))
    return items


def verify(root: Path, ctx: VerifyContext, *, max_steps: int | None = None) -> VerifierReport:
    """Score the recipe at ``root`` (module docstring). ``max_steps`` shortens every episode's
    horizon (tests only; the report records it)."""
    from rle_tasks.envs.libero import replay
    from rle_tasks.envs.libero.replay import CKPT, SOLUTION, check_solution, train

    full = episode_set()
    n = ctx.episodes or (QUICK_EPISODES if ctx.quick else len(full))
    n = min(n, len(full))
    rub = rubric(TASK_ID, n)
    partial = n < len(full)
    native: dict = {"episodes_requested": n, "episode_set": len(full), "partial": partial, "quick": ctx.quick}
    if max_steps is not None:
        native["max_steps_override"] = int(max_steps)
    root = Path(root).resolve()
    path = root / SOLUTION
    fault = check_solution(path)
    if fault is None and not path.resolve().is_relative_to(root):
        fault = ("f05.no_solution", f"{SOLUTION} points outside the submission directory")
    if fault is not None:
        return rub.report(
            {}, valid=False, errors=[ErrorEntry(*fault)], caps=["replay_failed"], native_metrics=native
        )
    demos = dataset_dir()
    native["dataset_sha256"] = _dataset(demos)
    trained = Path(tempfile.mkdtemp(prefix="rle-f05c-"))
    try:
        t0 = time.monotonic()
        fault = train(path, demos, trained, budget_s=replay.TRAIN_BUDGET_S)
        native["train_s"] = round(time.monotonic() - t0, 3)
        if fault is not None:
            return rub.report(
                {}, valid=True, errors=[ErrorEntry(*fault)], caps=["replay_failed"], native_metrics=native
            )
        ckpt = (trained / CKPT).read_bytes()
        meta = (trained / "meta.json").read_bytes() if (trained / "meta.json").is_file() else None
    finally:
        shutil.rmtree(trained, ignore_errors=True)
    native["ckpt_bytes"] = len(ckpt)
    native["ckpt_sha256"] = hashlib.sha256(ckpt).hexdigest()
    episodes = episode_order(ctx)[:n]
    items = units(episodes, path.read_bytes(), ckpt, meta, max_steps)
    results = run_parallel(run_unit, items, jobs=ctx.jobs, executor=ctx.executor, ray_address=ctx.ray_address)
    runs = [r for unit in results for r in unit]
    return _report(rub, runs, n, native)


def _report(rub, runs: list[dict], n: int, native: dict) -> VerifierReport:
    successes = sum(bool(r["success"]) for r in runs)
    complete = sum(not r["fault"] for r in runs)
    need = required_complete(n)
    faults: dict[str, int] = {}
    for r in runs:
        if r["fault"]:
            faults[r["fault"]] = faults.get(r["fault"], 0) + 1
    per_task: dict[str, dict[str, int]] = {}
    for r in runs:
        e = per_task.setdefault(str(r["task"]), {"episodes": 0, "successes": 0})
        e["episodes"] += 1
        e["successes"] += int(bool(r["success"]))
    errors = []
    for code, count in sorted(faults.items()):
        example = next((r.get("message") for r in runs if r["fault"] == code and r.get("message")), "")
        errors.append(
            ErrorEntry(
                code,
                f"{count} of {n} episodes ended by a fault of the served policy"
                + (f": {example}" if example else ""),
            )
        )
    caps = []
    if complete < need:
        caps.append("incomplete")
        errors.append(ErrorEntry("f05.incomplete", f"{complete} of {n} episodes completed; {need} required"))
    rate = successes / n if n else 0.0
    native |= {
        "successes": successes,
        "success_rate": rate,
        "complete": complete,
        "required_complete": need,
        "per_task": dict(sorted(per_task.items(), key=lambda kv: int(kv[0]))),
        "episodes": [{k: v for k, v in r.items() if k != "message"} for r in runs],
        "mean_steps": float(np.mean([r["steps"] for r in runs])) if runs else 0.0,
    }
    outcome = Outcome(
        {"episodes": rate}, f"{successes} of {n} episodes succeeded", {"successes": successes, "episodes": n}
    )
    return rub.report({"success_rate": outcome}, valid=True, errors=errors, caps=caps, native_metrics=native)


__all__ = ["TASK_ID", "episode_order", "episode_set", "run_unit", "units", "verify"]
