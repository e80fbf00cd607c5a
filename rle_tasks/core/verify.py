"""Running a task's verifier on an artifact directory: the guard shared by every family.

The guard fills the report's provenance fields (artifact digest, secret label, seed digest, timing,
the sandbox isolation layers active in this environment),
turns unreadable input into a participant fault, and turns our own bugs into an internal fault with
the traceback in the report instead of an exception escaping to the user.
"""

from __future__ import annotations

import time
import traceback
from pathlib import Path

from rle_design.errors import RleError
from rle_tasks.core.report import ErrorEntry, VerifierReport, artifact_sha256
from rle_tasks.core.runtime.secrets import seed_digest
from rle_tasks.core.task import TaskSpec, VerifyContext


class InternalVerifierFault(RleError):
    """A bug of ours inside a verifier (exit code 1)."""

    code = "verifier.internal"


class VerifierSetupError(RleError):
    """The verifier's own environment lacks something it needs (a dataset not built, a side
    environment missing): the operator's fault, not the artifact's. ``run_verify`` lets it through
    (exit code 2, the message says how to fix it) instead of writing a report."""

    code = "verifier.setup"


def _sandbox_layers() -> dict[str, bool]:
    """Isolation layers a sandboxed child gets here (all off when no child can start)."""
    from rle_design.sandbox import LAYERS, probe_layers

    try:
        return probe_layers()
    except RleError:
        return dict.fromkeys(LAYERS, False)


def empty_report(task: TaskSpec) -> VerifierReport:
    return VerifierReport(task_id=task.id, family=f"{task.family:02d}", workflow=task.workflow)


def run_verify(task: TaskSpec, artifact_dir: str | Path, ctx: VerifyContext) -> tuple[VerifierReport, bool]:
    """Verify ``artifact_dir`` for ``task``.

    Returns:
        The report and whether an internal fault (our bug) occurred.

    Raises:
        RleError: The task is not implemented, or ``--episodes`` given to a task not scored over
            episodes (usage errors, exit code 2).
        VerifierSetupError: The verifier's environment is incomplete (exit code 2).
    """
    if task.verify is None:
        raise RleError(
            f"task '{task.id}' is registered but not implemented yet; implemented tasks are listed by "
            "`rle tasks` with implemented = yes",
            code="task.not_implemented",
        )
    if ctx.episodes is not None and not task.episode_scored:
        raise RleError(
            f"task '{task.id}' is not scored over episodes: --episodes does not apply (use --quick for "
            "its reduced batteries)",
            code="task.no_episodes",
        )
    if ctx.episodes is not None and ctx.episodes < 1:
        raise RleError(f"--episodes must be at least 1, got {ctx.episodes}", code="task.no_episodes")
    t0 = time.perf_counter()
    root = Path(artifact_dir)
    internal = False
    if not root.is_dir():
        report = empty_report(task).replace(
            errors=(
                ErrorEntry(
                    "artifact.missing_dir",
                    f"artifact directory '{root}' does not exist or is not a directory",
                ),
            )
        )
    else:
        try:
            report = task.verify(root, ctx)
        except VerifierSetupError:
            raise
        except Exception as exc:  # our bug: keep a report and say so
            internal = True
            message = f"internal verifier fault {type(exc).__name__}: {exc}\n{traceback.format_exc(limit=20)}"
            report = empty_report(task).replace(errors=(ErrorEntry(InternalVerifierFault.code, message),))
        report = report.replace(artifact_sha256=artifact_sha256(root))
    if not ctx.secret.public:  # participant text never leaves a private verification
        report = report.withheld()
    report = report.replace(
        secret=ctx.secret.label,
        partial=bool((ctx.quick and task.quick_reduces) or report.native_metrics.get("partial") is True),
        seed_digest=seed_digest(ctx.secret, task.id),
        elapsed_s=time.perf_counter() - t0,
        sandbox_layers=_sandbox_layers(),
    )
    return report, internal
