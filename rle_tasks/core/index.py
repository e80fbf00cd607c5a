"""RLE Index (paper eq. 1): task scores -> family means -> workflow means -> mean of the four workflows.

Every task registered for a family counts in that family's mean; a task without a report scores 0 and
is listed in ``IndexResult.missing``, never silently dropped. Means are computed with exact rational
arithmetic so the result does not depend on the order of the reports.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

from rle_design.errors import RleError
from rle_tasks.core.development import Progress
from rle_tasks.core.diagnostics import native_scalars, task_diagnostics
from rle_tasks.core.report import VerifierReport
from rle_tasks.core.task import WORKFLOW_ORDER, WORKFLOWS, TaskSpec

ReportLike = VerifierReport | dict[str, Any] | str | os.PathLike


@dataclass(frozen=True)
class IndexResult:
    """Scores at every level of the aggregation, all in [0, 1].

    Attributes:
        name: System name shown on the leaderboard.
        task_scores: Score of every registered task, 0 for missing ones (registry order).
        family_scores: Mean task score per family number.
        workflow_scores: Mean family score per workflow (``WORKFLOW_ORDER``).
        index: The RLE Index, the mean of the four workflow scores.
        missing: Registered task ids without a report.
        sources: Where each reported task's score came from (file path or ``report #i``).
        partial: Reported task ids whose score comes from a reduced evaluation (``allow_partial``).
        native: Each reported task's scalar native metrics (``native_scalars``).
        diagnostics: Each reported task's family diagnostics (``diagnostics.task_diagnostics``: labelled
            numbers with units), for the page's family sections.
        development: Each task's development progress per trial (Harbor jobs whose development sessions
            ran episodes: ``rle_tasks.core.development``).
    """

    name: str
    task_scores: dict[str, float]
    family_scores: dict[int, float]
    workflow_scores: dict[str, float]
    index: float
    missing: tuple[str, ...]
    sources: dict[str, str] = field(default_factory=dict)
    partial: tuple[str, ...] = ()
    native: dict[str, dict[str, Any]] = field(default_factory=dict)
    diagnostics: dict[str, dict[str, float]] = field(default_factory=dict)
    development: dict[str, tuple[Progress, ...]] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (family keys as ``"F01"`` ...)."""
        return {
            "name": self.name,
            "rle_index": self.index,
            "workflow_scores": dict(self.workflow_scores),
            "family_scores": {f"F{k:02d}": v for k, v in self.family_scores.items()},
            "task_scores": dict(self.task_scores),
            "missing": list(self.missing),
            "partial": list(self.partial),
        }


def _load(item: ReportLike, position: int) -> tuple[VerifierReport, str]:
    """A report and a label naming where it came from."""
    if isinstance(item, VerifierReport):
        return item, f"report #{position}"
    if isinstance(item, dict):
        label = f"report #{position}"
        data = item
    else:
        path = Path(item)
        label = str(path)
        if path.is_dir():
            raise RleError(
                f"{path} is a directory; pass the report files (e.g. {path}/*.json)", code="index.input"
            )
        try:
            text = path.read_text()
        except FileNotFoundError:
            raise RleError(f"report file {path} does not exist", code="index.input", path=str(path)) from None
        except OSError as exc:
            raise RleError(f"cannot read report file {path}: {exc.strerror}", code="index.input") from None
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise RleError(
                f"report file {path} is not JSON: {exc}", code="index.input", path=str(path)
            ) from None
    if not isinstance(data, dict) or not isinstance(data.get("task_id"), str):
        raise RleError(f"{label} is not a verifier report (no 'task_id' field)", code="index.input")
    try:
        return VerifierReport.from_dict(data), label
    except (KeyError, TypeError, ValueError) as exc:
        raise RleError(f"{label} is not a valid verifier report: {exc!r}", code="index.input") from None


def _mean(values: Sequence[Fraction]) -> Fraction:
    return sum(values, Fraction(0)) / len(values) if values else Fraction(0)


def compute_index(
    reports: Iterable[ReportLike],
    *,
    name: str = "submission",
    tasks: Sequence[TaskSpec] | None = None,
    allow_privileged: bool = False,
    allow_partial: bool = False,
) -> IndexResult:
    """Aggregate verifier reports into the RLE Index.

    Args:
        reports: ``VerifierReport`` objects, report dicts, or paths to report JSON files.
        name: System name for tables and figures.
        tasks: The task set (default: every registered task, ``registry.all_tasks()``).
        allow_privileged: Accept reports of privileged sessions (``ledger.privileged``: an operator's
            oracle trial, never an agent's result).
        allow_partial: Accept reports of a reduced evaluation (``VerifierReport.partial``); the result
            lists them (``partial``) and the tables and page mark them.

    Returns:
        The scores at task, family and workflow level and the index.

    Raises:
        RleError: A report is unreadable, names an unknown task, has a score outside [0, 1], or two
            reports name the same task (``code`` ``index.input``, ``index.unknown_task``,
            ``index.score`` or ``index.duplicate``), or a report is of a privileged session and
            ``allow_privileged`` is not set (``index.privileged``), or a report is partial and
            ``allow_partial`` is not set (``index.partial``).
    """
    if tasks is None:
        from rle_tasks.core.registry import all_tasks

        tasks = all_tasks()
    known = {t.id: t for t in tasks}
    scores: dict[str, Fraction] = {}
    sources: dict[str, str] = {}
    partial: list[str] = []
    native: dict[str, dict[str, Any]] = {}
    diagnostics: dict[str, dict[str, float]] = {}
    for i, item in enumerate(reports):
        report, label = _load(item, i)
        tid = report.task_id
        if tid not in known:
            family = tid.split("-")[0]
            close = [k for k in known if k.split("-")[0] == family] or list(known)
            raise RleError(
                f"{label} names unknown task '{tid}'. Known ids: {', '.join(close)}",
                code="index.unknown_task",
            )
        if not allow_privileged and any(e.code == "ledger.privileged" for e in report.errors):
            raise RleError(
                f"{label} (task '{tid}') comes from a privileged session (an operator's oracle trial), not "
                "an agent's result; index it only on purpose (--allow-privileged)",
                code="index.privileged",
            )
        if report.partial and not allow_partial:
            raise RleError(
                f"{label} (task '{tid}') was verified on a reduced evaluation (quick mode or a subset): the "
                "index is computed on full scores; verify it in full, or index partial scores on purpose "
                "(--allow-partial marks them)",
                code="index.partial",
            )
        if tid in scores:
            raise RleError(
                f"two reports for task '{tid}': {sources[tid]} and {label}; pass one report per task",
                code="index.duplicate",
            )
        score = float(report.score)
        if not math.isfinite(score) or not 0.0 <= score <= 1.0:
            raise RleError(f"{label} (task '{tid}') has score {score}, outside [0, 1]", code="index.score")
        scores[tid] = Fraction(score)
        sources[tid] = label
        if report.partial:
            partial.append(tid)
        native[tid] = native_scalars(report.native_metrics)
        diagnostics[tid] = task_diagnostics(report)

    by_family: dict[int, list[Fraction]] = {}
    for t in tasks:
        by_family.setdefault(t.family, []).append(scores.get(t.id, Fraction(0)))
    family = {f: _mean(v) for f, v in sorted(by_family.items())}
    workflow = {w: _mean([family[f] for f in sorted(family) if WORKFLOWS[f] == w]) for w in WORKFLOW_ORDER}
    index = _mean(list(workflow.values()))
    return IndexResult(
        name=name,
        task_scores={t.id: float(scores.get(t.id, 0)) for t in tasks},
        family_scores={f: float(v) for f, v in family.items()},
        workflow_scores={w: float(v) for w, v in workflow.items()},
        index=float(index),
        missing=tuple(t.id for t in tasks if t.id not in scores),
        sources=sources,
        partial=tuple(t.id for t in tasks if t.id in partial),
        native={t.id: native[t.id] for t in tasks if t.id in native},
        diagnostics={t.id: diagnostics[t.id] for t in tasks if t.id in diagnostics},
    )


def format_tables(result: IndexResult, tasks: Sequence[TaskSpec] | None = None) -> str:
    """Family, workflow and index tables plus the missing list, as plain text (scores in percent)."""
    if tasks is None:
        from rle_tasks.core.registry import all_tasks

        tasks = all_tasks()
    counts: dict[int, list[int]] = {}
    for t in tasks:
        c = counts.setdefault(t.family, [0, 0])
        c[1] += 1
        c[0] += t.id not in result.missing
    lines = [f"RLE Index for {result.name}", "", f"{'family':<8}{'workflow':<24}{'reported':>10}{'score':>9}"]
    for f, s in result.family_scores.items():
        lines.append(f"F{f:02d}     {WORKFLOWS[f]:<24}{f'{counts[f][0]}/{counts[f][1]}':>10}{100 * s:>8.1f}%")
    lines += ["", f"{'workflow':<32}{'score':>9}"]
    for w, s in result.workflow_scores.items():
        lines.append(f"{w:<32}{100 * s:>8.1f}%")
    mark = " (includes partial scores)" if result.partial else ""
    lines += ["", f"{'RLE Index':<32}{100 * result.index:>8.1f}%{mark}", ""]
    if result.partial:
        lines.append(
            f"partial ({len(result.partial)} tasks, reduced evaluation): {', '.join(result.partial)}"
        )
    if result.missing:
        lines.append(f"missing ({len(result.missing)} tasks, scored 0):")
        by_fam: dict[str, list[str]] = {}
        for tid in result.missing:
            by_fam.setdefault(tid.split("-")[0], []).append(tid)
        for fam, ids in by_fam.items():
            lines.append(f"  F{fam}: {', '.join(ids)}")
    else:
        lines.append("missing: none")
    return "\n".join(lines)
