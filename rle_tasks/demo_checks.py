"""Whether ``rle demo`` reproduced the pinned results: scores against the solutions' golden scores
(quick and, where pinned, full), and retrained checkpoints against the earlier ones."""

from __future__ import annotations

from rle_tasks.core.registry import all_tasks
from rle_tasks.core.solutions import declaration

GOLDEN_TOLERANCE = 1e-6
"""Largest difference from a golden score that still counts as reproduced (scores are written to 12
digits)."""


def golden_differences(results, modes: dict[tuple[str, str], bool]) -> dict[tuple[str, str], float]:
    """(task, solution) -> golden score, for the reports made with the public development key whose
    score differs from the solution's golden score by more than ``GOLDEN_TOLERANCE``: a quick report
    against ``Solution.quick_score``, a full one against ``Solution.full_score`` where that is pinned."""
    tasks = {t.id: t for t in all_tasks()}
    out = {}
    for task_id, name, _, rep in results:
        if rep.secret != "public":
            continue
        sol = declaration(tasks[task_id]).get(name)
        golden = sol.quick_score if modes.get((task_id, name)) else sol.full_score
        if golden is not None and abs(rep.score - golden) > GOLDEN_TOLERANCE:
            out[(task_id, name)] = golden
    return out


def unpinned_full(results, modes: dict[tuple[str, str], bool]) -> list[tuple[str, str]]:
    """(task, solution) of the full-mode reports whose solution pins no full golden score."""
    tasks = {t.id: t for t in all_tasks()}
    return [
        (t, n)
        for t, n, _, _ in results
        if not modes.get((t, n)) and declaration(tasks[t]).get(n).full_score is None
    ]


def retrainings(results) -> list[tuple[str, str, bool | None]]:
    """(task, solution, reproduced) of the reports that trained a recipe: ``reproduced`` says whether
    the checkpoint is byte-identical to the earlier training of the same recipe on the same data (the
    shipped checkpoint pinned by sha256 on a machine whose training cache is empty), None where there
    was none to compare with."""
    out = []
    for t, n, _, rep in results:
        native = rep.native_metrics or {}
        if native.get("training") == "trained":
            out.append((t, n, native.get("ckpt_reproduced")))
    return out
