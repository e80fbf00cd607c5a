"""Whether ``rle demo`` reproduced the pinned results: scores against the golden scores (quick:
``Solution.quick_score``; full: ``FULL_GOLDENS``, where pinned), and retrained checkpoints against the
earlier ones."""

from __future__ import annotations

import json
from pathlib import Path

from rle_tasks.core.registry import all_tasks
from rle_tasks.core.solutions import declaration

FULL_GOLDENS = Path(__file__).with_name("full_goldens.json")
"""Golden scores in full mode with the public development key, ``{"task:solution": score}``: the
``full_scores.json`` that ``rle demo --full`` writes, copied here from a run on the 2-core reference
machine (the date and the run are in benchmarks/README.md)."""

GOLDEN_TOLERANCE = 1e-6
"""Largest difference from a golden score that still counts as reproduced (scores are written to 12
digits)."""


def full_goldens() -> dict[str, float]:
    """``FULL_GOLDENS`` (empty where the file is absent)."""
    try:
        return {str(k): float(v) for k, v in json.loads(FULL_GOLDENS.read_text()).items()}
    except (OSError, ValueError, AttributeError):
        return {}


def golden_differences(results, modes: dict[tuple[str, str], bool]) -> dict[tuple[str, str], float]:
    """(task, solution) -> golden score, for the reports made with the public development key whose
    score differs from the golden score by more than ``GOLDEN_TOLERANCE``: a quick report against
    ``Solution.quick_score``, a full one against ``FULL_GOLDENS`` where it is pinned there."""
    tasks = {t.id: t for t in all_tasks()}
    full = full_goldens()
    out = {}
    for task_id, name, _, rep in results:
        if rep.secret != "public":
            continue
        if modes.get((task_id, name)):
            golden = declaration(tasks[task_id]).get(name).quick_score
        else:
            golden = full.get(f"{task_id}:{name}")
        if golden is not None and abs(rep.score - golden) > GOLDEN_TOLERANCE:
            out[(task_id, name)] = golden
    return out


def unpinned_full(results, modes: dict[tuple[str, str], bool]) -> list[tuple[str, str]]:
    """(task, solution) of the full-mode reports that ``FULL_GOLDENS`` has no golden score for."""
    full = full_goldens()
    return [(t, n) for t, n, _, _ in results if not modes.get((t, n)) and f"{t}:{n}" not in full]


def full_scores(results, modes: dict[tuple[str, str], bool]) -> dict[str, float]:
    """``{"task:solution": score}`` of the full-mode reports with the public key (what pins
    ``FULL_GOLDENS``)."""
    return {
        f"{t}:{n}": rep.score for t, n, _, rep in results if not modes.get((t, n)) and rep.secret == "public"
    }


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
