"""Replay of a family-05 recipe: check ``solution.py``, train it once offline, serve it, run episodes.

The submitted artifact is one UTF-8 ``solution.py`` of at most 1 MiB with two entry points, each run
in the project sandbox in a fresh directory holding only ``solution.py`` (development checkpoints are
never transferred):

* ``train(demos_dir)``: reads the demonstrations (``demos_dir``, a read-only copy: one ``.npz`` per
  episode with ``actions``, ``state``, ``sim_states``, ``language``, see ``demos.py``) and writes
  ``ckpt.pt`` (and optionally ``meta.json``) into its working directory, within the training budget
  (the card: 1,800 s plus a 120 s allowance);
* ``serve(socket_path)``: loads ``ckpt.pt`` (and ``meta.json``) from its working directory and
  speaks the policy socket protocol (``rle_design.policy_socket``).

``replay`` returns per-episode results; a contract, training or checkpoint fault ends it with a named
code (``f05.*`` or the sandbox's ``sandbox.*``) and no episode. A run on fewer episodes than the
task's fixed set is marked partial: it is never an official score.
"""

from __future__ import annotations

import contextlib
import dataclasses
import shutil
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from rle_design.policy_socket import ProtocolError
from rle_design.sandbox import ParticipantFault, Sandbox, SandboxLimits
from rle_tasks.envs.libero import LiberoEnv
from rle_tasks.envs.libero.client import EpisodeResult, run_episode, serving

SOLUTION = "solution.py"
SOLUTION_MAX_BYTES = 1 << 20
TRAIN_BUDGET_S = 1800.0 + 120.0
"""Training wall time: the card's 1,800 s plus its 120 s infrastructure allowance [s]."""
CKPT = "ckpt.pt"
CKPT_MAX_BYTES = 4 << 30
TRAIN_CPUS = 48
"""CPU cores of the card's replay machine: training may keep them busy for the whole budget."""
TRAIN_LIMITS = SandboxLimits(
    cpu_seconds=TRAIN_CPUS * TRAIN_BUDGET_S,
    memory_bytes=64 << 30,
    file_bytes=CKPT_MAX_BYTES,
    max_processes=4096,  # threads of torch and BLAS; fork and exec stay refused by the audit hook
    call_timeout_s=TRAIN_BUDGET_S,
)


@dataclass
class ReplayResult:
    """What a replay did.

    Attributes:
        fault: ``(code, message)`` that stopped the replay before any episode, or None.
        train_s: Wall time of training [s].
        episodes: Per-episode results, in the order run.
        requested: Episodes the task's fixed set holds (the denominator of an official score).
    """

    fault: tuple[str, str] | None = None
    train_s: float = 0.0
    episodes: list[EpisodeResult] = field(default_factory=list)
    requested: int = 0

    @property
    def partial(self) -> bool:
        return len(self.episodes) < self.requested

    @property
    def success_rate(self) -> float:
        """Successes over the requested episodes (missing episodes fail) [1]."""
        return sum(e.success for e in self.episodes) / self.requested if self.requested else 0.0


def check_solution(path: Path) -> tuple[str, str] | None:
    """The artifact contract: ``(code, message)`` of the first violation, or None."""
    path = Path(path)
    if not path.is_file() or path.is_symlink():
        return ("f05.no_solution", f"{path.name} is missing (a regular file named {SOLUTION})")
    size = path.stat().st_size
    if size > SOLUTION_MAX_BYTES:
        return (
            "f05.solution_too_large",
            f"{path.name} has {size} B, more than {SOLUTION_MAX_BYTES} B (1 MiB)",
        )
    try:
        path.read_bytes().decode("utf-8")
    except UnicodeDecodeError as exc:
        return ("f05.solution_encoding", f"{path.name} is not UTF-8: {exc}")
    return None


def train(
    solution: Path, demos_dir: Path, out_dir: Path, budget_s: float = TRAIN_BUDGET_S
) -> tuple[str, str] | None:
    """Run ``train`` of ``solution`` alone in the sandbox and copy its ``ckpt.pt`` (and ``meta.json``)
    into ``out_dir``; ``(code, message)`` of a fault, or None."""
    stage = Path(tempfile.mkdtemp(prefix="rle-f05t-"))
    try:
        shutil.copyfile(solution, stage / SOLUTION)
        demos = {f"demos/{p.name}": p for p in sorted(Path(demos_dir).iterdir()) if p.is_file()}
        limits = dataclasses.replace(TRAIN_LIMITS, call_timeout_s=budget_s, cpu_seconds=TRAIN_CPUS * budget_s)
        try:
            with Sandbox(stage / SOLUTION, limits=limits, workdir_files=demos, name="solution") as box:
                if not box.has("train") or not box.has("serve"):
                    return (
                        "f05.entry_point",
                        "solution.py must define train(demos_dir) and serve(socket_path)",
                    )
                box.call("train", "demos")
                ckpt = box.workdir / CKPT
                if not ckpt.is_file() or ckpt.stat().st_size == 0:
                    return (
                        "f05.no_checkpoint",
                        f"train() wrote no {CKPT} (or an empty one) in its directory",
                    )
                out_dir.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(ckpt, out_dir / CKPT)
                if (box.workdir / "meta.json").is_file():
                    shutil.copyfile(box.workdir / "meta.json", out_dir / "meta.json")
        except ParticipantFault as exc:
            return (exc.code, exc.message)
        return None
    finally:
        shutil.rmtree(stage, ignore_errors=True)


def replay(
    solution: Path,
    demos_dir: Path,
    episodes: list[tuple[int, int]],
    *,
    requested: int | None = None,
    suite: str = "libero_10",
    max_steps: int | None = None,
    budget_s: float = TRAIN_BUDGET_S,
    envs: dict[int, LiberoEnv] | None = None,
) -> ReplayResult:
    """Check, train, serve and evaluate ``solution`` on ``episodes`` ((task id, initial state) pairs).

    Args:
        requested: Episodes of the task's fixed set (default ``len(episodes)``); fewer run is partial.
        max_steps: Horizon override (default: each task's).
        budget_s: Training wall time [s].
        envs: Rendering environments already started, by task id (the caller closes them); the
            other tasks get their own.
    """
    res = ReplayResult(requested=len(episodes) if requested is None else int(requested))
    res.fault = check_solution(Path(solution))
    if res.fault:
        return res
    serve_dir = Path(tempfile.mkdtemp(prefix="rle-f05r-"))
    try:
        shutil.copyfile(solution, serve_dir / SOLUTION)
        t0 = time.monotonic()
        res.fault = train(Path(solution), Path(demos_dir), serve_dir, budget_s)
        res.train_s = time.monotonic() - t0
        if res.fault:
            return res
        by_task: dict[int, list[int]] = {}
        for task_id, init in episodes:
            by_task.setdefault(int(task_id), []).append(int(init))
        try:
            with serving(serve_dir) as policy:
                k = 0
                for task_id, inits in sorted(by_task.items()):
                    given = (envs or {}).get(task_id)
                    with contextlib.nullcontext(given) if given else LiberoEnv(suite, task_id) as env:
                        for init in inits:
                            res.episodes.append(
                                run_episode(env, policy, init, episode=k, max_steps=max_steps)
                            )
                            k += 1
        except ProtocolError as exc:  # the policy never connected: no episode ran
            res.fault = (exc.code, exc.message)
        return res
    finally:
        shutil.rmtree(serve_dir, ignore_errors=True)
