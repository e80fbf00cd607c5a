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
        native: Each reported task's scalar native metrics (``native_scalars``), for the page's
            per-family diagnostics.
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


NATIVE_COLUMNS = 8
"""Most native metrics shown per family on the page (the first ones the family's reports share)."""
BOOKKEEPING = frozenset({"quick", "partial", "secret", "seed_digest", "attempt", "secret_private"})
"""Native keys that say how a report was made, not what was measured: left off the diagnostics."""


def native_scalars(metrics: dict[str, Any], limit: int = 24) -> dict[str, Any]:
    """The top-level numbers, flags and short words of a report's native metrics (a family's own
    diagnostics: clearance and parts/min, MPJPE and survival, per-arm results ...), in report order."""
    out: dict[str, Any] = {}
    for key, value in metrics.items():
        if key in BOOKKEEPING:
            continue
        number = isinstance(value, int | float) and (isinstance(value, bool) or math.isfinite(value))
        if number or (isinstance(value, str) and len(value) <= 24):
            out[key] = value
        if len(out) >= limit:
            break
    return out


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


_LABELS = {
    "interactive_control": "Interactive control",
    "policy_learning": "Policy learning",
    "perception_estimation": "Perception & estimation",
    "mechanical_design": "Mechanical design",
}


def _png(fig: Any) -> str:
    """A matplotlib figure as a base64 PNG string (the figure is closed)."""
    import base64
    import io

    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, bbox_inches="tight")
    plt.close(fig)
    return base64.b64encode(buf.getvalue()).decode("ascii")


def leaderboard_figure(results: Sequence[IndexResult]) -> str:
    """Grouped bars: RLE Index and the four workflow scores [%] per system, as a base64 PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    ranked = sorted(results, key=lambda r: -r.index)
    labels = ["RLE Index"] + [_LABELS[w].replace(" ", "\n", 1) for w in WORKFLOW_ORDER]
    x = np.arange(len(labels))
    width = 0.8 / len(ranked)
    fig, ax = plt.subplots(figsize=(8.5, 3.8))
    for i, r in enumerate(ranked):
        vals = [100 * r.index] + [100 * r.workflow_scores[w] for w in WORKFLOW_ORDER]
        bars = ax.bar(x + (i - (len(ranked) - 1) / 2) * width, vals, width, label=r.name)
        ax.bar_label(bars, fmt="%.1f", fontsize=8)
    ax.set_xticks(x, labels, fontsize=9)
    ax.set_ylim(0, 105)
    ax.set_ylabel("score [%]")
    ax.set_title("RLE-Bench leaderboard")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(axis="y", alpha=0.3)
    return _png(fig)


def profile_figure(results: Sequence[IndexResult]) -> str:
    """Radar chart of the per-workflow capability profile of each system, as a base64 PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    angles = np.linspace(0, 2 * np.pi, len(WORKFLOW_ORDER), endpoint=False)
    closed = np.concatenate([angles, angles[:1]])
    fig, ax = plt.subplots(figsize=(5, 5), subplot_kw={"polar": True})
    for r in results:
        vals = [100 * r.workflow_scores[w] for w in WORKFLOW_ORDER]
        ax.plot(closed, vals + vals[:1], marker="o", label=r.name)
        ax.fill(closed, vals + vals[:1], alpha=0.15)
    ax.set_xticks(angles, [_LABELS[w].replace(" ", "\n", 1) for w in WORKFLOW_ORDER], fontsize=9)
    ax.set_ylim(0, 100)
    ax.set_title("Capability profile (workflow scores, %)", pad=20)
    ax.legend(fontsize=8, loc="lower right", bbox_to_anchor=(1.25, -0.1))
    return _png(fig)


def write_index_html(results: Sequence[IndexResult], path: Path, resources_section: str = "") -> Path:
    """Self-contained HTML page (figures embedded as base64 PNGs) with the leaderboard and tables.

    Args:
        results: One index result per system.
        path: Output file.
        resources_section: HTML placed after the leaderboard: for Harbor job directories the
            performance-versus-cost figure, the resources table and the failed trials
            (``harbor_results.resources_section``).
    """
    from html import escape

    if not results:
        raise RleError("no results to show", code="index.input")
    board = leaderboard_figure(results)
    profile = profile_figure(results)
    cost = resources_section
    head = "".join(f"<th>{escape(r.name)}</th>" for r in results)

    def row(label: str, values: list[float]) -> str:
        return f"<tr><td>{escape(label)}</td>" + "".join(f"<td>{100 * v:.1f}</td>" for v in values) + "</tr>"

    rows = [row("RLE Index" + (" (includes partial scores)" if any(r.partial for r in results) else ""),
                [r.index for r in results])]  # fmt: skip
    rows += [row(_LABELS[w], [r.workflow_scores[w] for r in results]) for w in WORKFLOW_ORDER]
    fam_rows = [
        row(f"F{f:02d} ({_LABELS[WORKFLOWS[f]]})", [r.family_scores[f] for r in results])
        for f in results[0].family_scores
    ]
    missing = "".join(
        f"<h3>{escape(r.name)}: {len(r.missing)} missing tasks (scored 0)</h3><p>"
        + (escape(", ".join(r.missing)) or "none")
        + "</p>"
        for r in results
    )
    diagnostics = _diagnostics_html(results)
    partial = "".join(
        f"<h3>{escape(r.name)}: {len(r.partial)} partial scores</h3><p>"
        + escape(", ".join(r.partial))
        + "</p><p>These tasks were verified on a reduced evaluation (quick mode or an episode subset); "
        "their scores are not a full verification's, and the index above includes them.</p>"
        for r in results
        if r.partial
    )
    page = f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>RLE Index</title>
<style>body{{font-family:sans-serif;margin:2em;max-width:1100px}}table{{border-collapse:collapse;margin:1em 0}}
td,th{{border:1px solid #ccc;padding:4px 10px;font-size:14px;text-align:right}}td:first-child{{text-align:left}}
</style></head><body>
<h1>RLE Index</h1>
<p>Task scores are averaged within each family (missing reports count 0), family scores within each
workflow, and the RLE Index is the mean of the four workflow scores (paper eq. 1). Scores in percent.</p>
<h2>Leaderboard</h2>
<img alt="leaderboard" src="data:image/png;base64,{board}">
<table><tr><th>score [%]</th>{head}</tr>{"".join(rows)}</table>
<h2>Capability profile (per workflow)</h2>
<img alt="capability profile" src="data:image/png;base64,{profile}">
{cost}
<h2>Families</h2>
<table><tr><th>family</th>{head}</tr>{"".join(fam_rows)}</table>
{diagnostics}
<h2>Missing reports</h2>{missing}
{"<h2>Partial scores</h2>" + partial if partial else ""}
</body></html>
"""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(page)
    return path


def _diagnostics_html(results: Sequence[IndexResult]) -> str:
    """One table per family: each reported task's scalar native metrics (the family's diagnostics)."""
    from html import escape

    rows: dict[int, list[tuple[str, str, dict[str, Any]]]] = {}
    for r in results:
        for tid, metrics in r.native.items():
            if metrics:
                rows.setdefault(int(tid.split("-")[0]), []).append((r.name, tid, metrics))
    if not rows:
        return ""

    def cell(v: Any) -> str:
        return escape(f"{v:.4g}" if isinstance(v, float) else str(v))

    out = [
        "<h2>Family diagnostics</h2><p>Each family's own measurements, from the reports' native metrics.</p>"
    ]
    for fam in sorted(rows):
        keys: list[str] = []
        for _, _, m in rows[fam]:
            keys += [k for k in m if k not in keys]
        keys = keys[:NATIVE_COLUMNS]
        head = "".join(f"<th>{escape(k)}</th>" for k in keys)
        body = "".join(
            f"<tr><td>{escape(name)}</td><td>{escape(tid)}</td>"
            + "".join(f"<td>{cell(m[k]) if k in m else ''}</td>" for k in keys)
            + "</tr>"
            for name, tid, m in rows[fam]
        )
        out.append(
            f"<h3>F{fam:02d} ({escape(_LABELS[WORKFLOWS[fam]])})</h3>"
            f"<table><tr><th>system</th><th>task</th>{head}</tr>{body}</table>"
        )
    return "".join(out)
