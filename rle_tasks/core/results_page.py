"""The RLE Index page: leaderboard, capability profile, (for Harbor jobs) performance against cost and
resources, then one section per family with its task scores per system and its native diagnostics,
as the paper's results pages and appendix show them. Figures are embedded PNGs: the page is one file.
"""

from __future__ import annotations

from collections.abc import Sequence
from html import escape
from pathlib import Path
from typing import Any

from rle_design.errors import RleError
from rle_tasks.core.diagnostics import mean_of
from rle_tasks.core.index import IndexResult
from rle_tasks.core.task import WORKFLOW_ORDER, WORKFLOWS, TaskSpec

WORKFLOW_LABELS = {
    "interactive_control": "Interactive control",
    "policy_learning": "Policy learning",
    "perception_estimation": "Perception & estimation",
    "mechanical_design": "Mechanical design",
}


def png(fig: Any) -> str:
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
    labels = ["RLE Index"] + [WORKFLOW_LABELS[w].replace(" ", "\n", 1) for w in WORKFLOW_ORDER]
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
    return png(fig)


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
    ax.set_xticks(angles, [WORKFLOW_LABELS[w].replace(" ", "\n", 1) for w in WORKFLOW_ORDER], fontsize=9)
    ax.set_ylim(0, 100)
    ax.set_title("Capability profile (workflow scores, %)", pad=20)
    ax.legend(fontsize=8, loc="lower right", bbox_to_anchor=(1.25, -0.1))
    return png(fig)


def write_index_html(results: Sequence[IndexResult], path: Path, resources_section: str = "") -> Path:
    """Self-contained HTML page (figures embedded as base64 PNGs) with the leaderboard and tables.

    Args:
        results: One index result per system.
        path: Output file.
        resources_section: HTML placed after the leaderboard: for Harbor job directories the
            performance-versus-cost figure, the resources table and the failed trials
            (``harbor.results.resources_section``).
    """
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
    rows += [row(WORKFLOW_LABELS[w], [r.workflow_scores[w] for r in results]) for w in WORKFLOW_ORDER]
    fam_rows = [
        row(f"F{f:02d} ({WORKFLOW_LABELS[WORKFLOWS[f]]})", [r.family_scores[f] for r in results])
        for f in results[0].family_scores
    ]
    missing = "".join(
        f"<h3>{escape(r.name)}: {len(r.missing)} missing tasks (scored 0)</h3><p>"
        + (escape(", ".join(r.missing)) or "none")
        + "</p>"
        for r in results
    )
    diagnostics = family_sections_html(results)
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
tr.mean td{{font-weight:bold}}section.family img{{max-width:100%}}
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
<h2>Family scores</h2>
<table><tr><th>family</th>{head}</tr>{"".join(fam_rows)}</table>
{diagnostics}
<h2>Missing reports</h2>{missing}
{"<h2>Partial scores</h2>" + partial if partial else ""}
</body></html>
"""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(page)
    return path


DOT_PLOT_TASKS = 6
"""Families with at most this many tasks get a dot plot (one row per task, one marker per system);
larger ones (01's and 02's fifteen) a heat map of task by system."""


def family_figure(results: Sequence[IndexResult], tasks: Sequence[TaskSpec]) -> str:
    """One family's task scores [%] for every system, as a base64 PNG; a task without a report is NA
    (left blank), distinct from a measured zero."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    ids = [t.id for t in tasks]
    values = np.array(
        [[np.nan if tid in r.missing else 100 * r.task_scores[tid] for r in results] for tid in ids]
    )
    if len(ids) > DOT_PLOT_TASKS:
        fig, ax = plt.subplots(figsize=(2.2 + 1.3 * len(results), 0.8 + 0.32 * len(ids)))
        cmap = matplotlib.colormaps["viridis"].with_extremes(bad="#e4e4e4")
        ax.imshow(np.ma.masked_invalid(values), cmap=cmap, vmin=0, vmax=100, aspect="auto")
        for (i, j), v in np.ndenumerate(values):
            text = "NA" if np.isnan(v) else f"{v:.0f}"
            ax.text(j, i, text, ha="center", va="center", fontsize=8, color="white" if v < 60 else "black")
        ax.set_xticks(range(len(results)), [r.name for r in results], fontsize=8, rotation=20, ha="right")
        ax.set_yticks(range(len(ids)), ids, fontsize=8)
    else:
        fig, ax = plt.subplots(figsize=(7.5, 0.9 + 0.45 * len(ids)))
        for j, r in enumerate(results):
            ys = np.arange(len(ids)) + (j - (len(results) - 1) / 2) * 0.12
            ax.scatter(values[:, j], ys, s=36, label=r.name, zorder=3)
            for y, v in zip(ys, values[:, j], strict=True):
                label, at, colour = ("NA", 0.0, "grey") if np.isnan(v) else (f"{v:.1f}", v, "black")
                ax.annotate(
                    label, (at, y), textcoords="offset points", xytext=(6, -3), fontsize=7, color=colour
                )
        ax.set_yticks(range(len(ids)), ids, fontsize=8)
        ax.set_xlim(-2, 110)
        ax.set_ylim(len(ids) - 0.5, -0.5)
        ax.set_xlabel("verifier reward [%]")
        ax.grid(axis="x", alpha=0.3)
        if len(results) > 1:
            ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return png(fig)


def _cell(v: float | None) -> str:
    if v is None:
        return ""
    return escape(f"{v:,.0f}" if abs(v) >= 1000 else f"{v:.4g}")


def family_sections_html(results: Sequence[IndexResult], tasks: Sequence[TaskSpec] | None = None) -> str:
    """One section per family with a report: its task-score figure and its diagnostics table (each
    system's reported tasks, then the family mean the paper's native-diagnostics table quotes)."""
    from rle_tasks.core.families import family

    if tasks is None:
        from rle_tasks.core.registry import all_tasks

        tasks = all_tasks()
    by_family: dict[int, list[TaskSpec]] = {}
    for t in tasks:
        by_family.setdefault(t.family, []).append(t)
    out = [
        "<h2>Family results</h2><p>Per family: every task's verifier reward per system (NA: no report), and the "
        "family's native diagnostics from the reports, in their own units. Diagnostics are not rewards: "
        "they are what the family measures (stage credits before caps, per-arm rewards, errors, rates).</p>"
    ]
    for fam, fam_tasks in sorted(by_family.items()):
        ids = [t.id for t in fam_tasks]
        if all(tid in r.missing for r in results for tid in ids):
            continue
        rows: list[str] = []
        labels: list[str] = []
        per_system: list[tuple[str, list[tuple[str, dict[str, float]]]]] = []
        partial = {(r.name, tid): " (partial)" for r in results for tid in r.partial}
        for r in results:
            got = [(tid, r.diagnostics[tid]) for tid in ids if r.diagnostics.get(tid)]
            per_system.append((r.name, got))
            for _, d in got:
                labels += [k for k in d if k not in labels]
        for name, got in per_system:
            for tid, d in got:
                rows.append(
                    f"<tr><td>{escape(name)}</td><td>{escape(tid)}{partial.get((name, tid), '')}</td>"
                    + "".join(f"<td>{_cell(d.get(k))}</td>" for k in labels)
                    + "</tr>"
                )
            if len(got) > 1:
                mean = mean_of([d for _, d in got])
                rows.append(
                    f"<tr class='mean'><td>{escape(name)}</td><td>family mean ({len(got)} tasks)</td>"
                    + "".join(f"<td>{_cell(mean.get(k))}</td>" for k in labels)
                    + "</tr>"
                )
        head = "".join(f"<th>{escape(k)}</th>" for k in labels)
        table = (
            f"<table class='diagnostics' data-family='{fam:02d}'><tr><th>system</th><th>task</th>{head}</tr>"
            f"{''.join(rows)}</table>"
            if labels
            else "<p>No diagnostics in these reports.</p>"
        )
        info = family(fam)
        out.append(
            f"<section class='family' id='f{fam:02d}'><h3>F{fam:02d} {escape(info.title)} "
            f"({escape(WORKFLOW_LABELS[WORKFLOWS[fam]])})</h3>"
            f"<img alt='F{fam:02d} task scores' src='data:image/png;base64,{family_figure(results, fam_tasks)}'>"
            f"{table}{_development_html(results, fam, ids)}</section>"
        )
    return "".join(out)


def _development_html(results: Sequence[IndexResult], fam: int, ids: Sequence[str]) -> str:
    figure = development_figure(results, ids)
    if figure is None:
        return ""
    return (
        "<p>Development progress, from the ledgers of the trials' development sessions (each episode the "
        "agent ran through the evaluation service).</p>"
        f"<img alt='F{fam:02d} development progress' src='data:image/png;base64,{figure}'>"
    )


def development_figure(results: Sequence[IndexResult], task_ids: Sequence[str]) -> str | None:
    """The paper's development-progress figure of a family (base64 PNG), or None when no trial of
    ``task_ids`` kept a development session with episodes (``rle_tasks.core.development``).

    Left: best development success so far against hours since the session opened, one line per trial,
    its official score as a diamond at the end. Right: episodes requested against the official score.
    """
    lines = [
        (f"{r.name} {tid}" + (f" #{i + 1}" if len(r.development[tid]) > 1 else ""), p)
        for r in results
        for tid in task_ids
        for i, p in enumerate(r.development.get(tid, ()))
    ]
    if not lines:
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 3.6))
    for label, p in lines:
        hours = [t / 3600.0 for t, _ in p.curve]
        line = left.step(hours, [100 * b for _, b in p.curve], where="post", label=label)[0]
        if p.official is not None:
            left.plot([hours[-1]], [100 * p.official], marker="D", color=line.get_color())
            right.scatter([p.episodes], [100 * p.official], color=line.get_color())
            right.annotate(
                label, (p.episodes, 100 * p.official), fontsize=7, xytext=(3, 3), textcoords="offset points"
            )
    left.set_xlabel("hours since the session opened")
    left.set_ylabel("best development success so far [%]")
    left.set_ylim(-2, 102)
    left.legend(fontsize=7, loc="lower right")
    left.set_title("development progress (diamond: official score)", fontsize=9)
    right.set_xlabel("development episodes requested")
    right.set_ylabel("official score [%]")
    right.set_ylim(-2, 102)
    right.set_xlim(0, 1.15 * max(p.episodes for _, p in lines))
    right.set_title("episodes requested against official score", fontsize=9)
    fig.tight_layout()
    return png(fig)
