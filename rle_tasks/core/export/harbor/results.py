"""Results back from Harbor: trial records of a job directory, grouped by system, into the RLE Index.

A Harbor 0.25 job directory holds one folder per trial, each with a ``result.json`` (``TrialResult``):
``task_name`` (``rle-bench/<task id>``), ``agent_info`` (agent name, ``model_info``),
``verifier_result.rewards`` (``reward`` is the task score written by ``tests/test.sh``),
``agent_result`` (input tokens including cached ones, cached tokens, output tokens, cost in USD),
``started_at``/``finished_at`` and ``exception_info``. The job's own ``result.json`` has no
``trial_name`` and is skipped.

A system is an agent with its model. A trial without a reward (a verifier fault, an agent crash, a
run that never finished) scores 0 and is listed as failed; several trials of one task are averaged;
tasks no trial reached are the index's missing tasks (also 0).
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from datetime import datetime
from fractions import Fraction
from pathlib import Path

from rle_design.errors import RleError
from rle_tasks.core.development import Episode, Progress, development_episodes, progress
from rle_tasks.core.diagnostics import mean_of
from rle_tasks.core.index import IndexResult, compute_index
from rle_tasks.core.task import WORKFLOWS, TaskSpec

ORG_PREFIX = "rle-bench/"


@dataclass(frozen=True)
class TrialRecord:
    """One Harbor trial.

    Attributes:
        system: ``agent (model)``, or the agent name when no model is recorded.
        task_id: RLE-Bench task id (the ``rle-bench/`` prefix removed).
        trial: Trial name (its folder).
        reward: The ``reward`` value, or None when the trial produced none (failed).
        cost_usd: Agent cost [USD] (0 when not reported).
        cost_reported: The agent reported a cost (some harnesses report none).
        input_tokens: Input tokens including cached ones.
        cached_tokens: Cached input tokens.
        output_tokens: Output tokens.
        elapsed_s: Trial wall time, ``finished_at - started_at`` [s] (0 when unknown).
        exception: ``Type: message`` of the recorded exception, or "".
        privileged: The reward says the session was privileged (an operator's oracle trial).
        partial: The reward comes from the task's quick evaluation (``RLE_VERIFY_QUICK=1``).
        diagnostics: The family diagnostics of the trial's verifier report.
        development: The episodes its development sessions ran (``development.development_episodes``).
    """

    system: str
    task_id: str
    trial: str
    reward: float | None
    cost_usd: float = 0.0
    cost_reported: bool = False
    input_tokens: int = 0
    cached_tokens: int = 0
    output_tokens: int = 0
    elapsed_s: float = 0.0
    exception: str = ""
    privileged: bool = False
    partial: bool = False
    diagnostics: dict[str, float] = field(default_factory=dict)
    development: tuple[Episode, ...] = ()

    @property
    def failed(self) -> bool:
        return self.reward is None


@dataclass(frozen=True)
class Resources:
    """Resources of one system over its trials (the paper's resources table).

    Means follow the RLE Index's hierarchy: a task's trials are averaged, then the tasks of a family,
    the families of a workflow and the workflows reached (a task without a trial is not averaged in;
    ``tasks`` says how many were reached). Totals sum every trial.

    Attributes:
        trials: Trials run.
        failed: Trials without a reward (scored 0).
        tasks: Distinct tasks with at least one trial.
        mean_cost_usd: Mean agent cost [USD] through the hierarchy.
        total_cost_usd: Summed agent cost [USD].
        cost_runs: Trials whose agent reported a cost (the paper's cost coverage).
        mean_elapsed_h: Mean trial wall time [h] through the hierarchy.
        input_tokens: Total input tokens (including cached).
        cached_tokens: Total cached input tokens.
        output_tokens: Total output tokens.
        failed_trials: ``task id/trial: reason`` of each failed trial.
    """

    trials: int
    failed: int
    tasks: int
    mean_cost_usd: float
    total_cost_usd: float
    cost_runs: int
    mean_elapsed_h: float
    input_tokens: int
    cached_tokens: int
    output_tokens: int
    failed_trials: tuple[str, ...] = ()


def _time(text: object) -> datetime | None:
    if not isinstance(text, str):
        return None
    try:
        return datetime.fromisoformat(text)
    except ValueError:
        return None


def _int(value: object) -> int:
    return int(value) if isinstance(value, int | float) and not isinstance(value, bool) else 0


def read_trial(path: Path) -> TrialRecord | None:
    """The record of one trial ``result.json`` (None for a file that is not a trial result).

    Raises:
        RleError: ``index.input`` when the file is not JSON.
    """
    try:
        data = json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as exc:
        raise RleError(f"cannot read Harbor trial result {path}: {exc}", code="index.input") from None
    if not isinstance(data, dict) or "trial_name" not in data or "task_name" not in data:
        return None
    agent = data.get("agent_info") or {}
    model = (agent.get("model_info") or {}).get("name")
    system = f"{agent.get('name', 'unknown')} ({model})" if model else str(agent.get("name", "unknown"))
    rewards = (data.get("verifier_result") or {}).get("rewards") or {}
    reward = rewards.get("reward")
    usage = data.get("agent_result") or {}
    start, end = _time(data.get("started_at")), _time(data.get("finished_at"))
    exc = data.get("exception_info") or {}
    return TrialRecord(
        system=system,
        task_id=str(data["task_name"]).removeprefix(ORG_PREFIX),
        trial=str(data["trial_name"]),
        reward=float(reward) if isinstance(reward, int | float) else None,
        cost_usd=float(usage.get("cost_usd") or 0.0),
        cost_reported=isinstance(usage.get("cost_usd"), int | float),
        input_tokens=_int(usage.get("n_input_tokens")),
        cached_tokens=_int(usage.get("n_cache_tokens")),
        output_tokens=_int(usage.get("n_output_tokens")),
        elapsed_s=(end - start).total_seconds() if start and end else 0.0,
        exception=f"{exc.get('exception_type')}: {exc.get('exception_message')}" if exc else "",
        privileged=bool(rewards.get("privileged")),
        partial=bool(rewards.get("partial")),
        diagnostics=_trial_diagnostics(path.parent / "verifier" / "report.json"),
        development=development_episodes(path.parent),
    )


def _trial_diagnostics(path: Path) -> dict[str, float]:
    """The family diagnostics of the verifier's report a trial kept (``verifier/report.json``); none
    when the trial has no readable report (a failed trial, an older export)."""
    from rle_tasks.core.diagnostics import task_diagnostics
    from rle_tasks.core.report import VerifierReport

    try:
        report = VerifierReport.from_dict(json.loads(path.read_text()))
        return task_diagnostics(report)
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return {}


def is_job_dir(path: Path) -> bool:
    """True for a directory holding at least one Harbor trial folder (``*/result.json``)."""
    return path.is_dir() and any(p.is_file() for p in path.glob("*/result.json"))


def read_job(job_dir: Path) -> list[TrialRecord]:
    """Every trial of a Harbor job directory, sorted by trial name.

    Raises:
        RleError: ``index.input`` when ``job_dir`` holds no trial results.
    """
    records = [r for p in sorted(Path(job_dir).glob("*/result.json")) if (r := read_trial(p)) is not None]
    if not records:
        raise RleError(f"{job_dir} holds no Harbor trial results (*/result.json)", code="index.input")
    return records


def hierarchical_mean(values: dict[str, list[float]]) -> float:
    """Mean of per-task values (``{task id: values of its trials}``) through the RLE Index's hierarchy:
    trials -> task -> family -> workflow -> the mean of the workflows reached (unknown ids are refused
    by ``systems``)."""
    from rle_tasks.core.registry import get_task

    families: dict[int, list[Fraction]] = {}
    for task_id, vals in values.items():
        if vals:
            families.setdefault(get_task(task_id).family, []).append(sum(map(Fraction, vals)) / len(vals))
    workflows: dict[str, list[Fraction]] = {}
    for fam, tasks in families.items():
        workflows.setdefault(WORKFLOWS[fam], []).append(sum(tasks) / len(tasks))
    means = [sum(f) / len(f) for f in workflows.values()]
    return float(sum(means) / len(means)) if means else 0.0


def resources(records: Sequence[TrialRecord]) -> Resources:
    """The resources row of one system's trials (``Resources``)."""
    cost: dict[str, list[float]] = {}
    hours: dict[str, list[float]] = {}
    for r in records:
        cost.setdefault(r.task_id, []).append(r.cost_usd)
        hours.setdefault(r.task_id, []).append(r.elapsed_s / 3600)
    failed = tuple(f"{r.task_id}/{r.trial}: {r.exception or 'no reward'}" for r in records if r.failed)
    return Resources(
        trials=len(records),
        failed=len(failed),
        tasks=len(cost),
        mean_cost_usd=hierarchical_mean(cost),
        total_cost_usd=float(sum(Fraction(r.cost_usd) for r in records)),
        cost_runs=sum(r.cost_reported for r in records),
        mean_elapsed_h=hierarchical_mean(hours),
        input_tokens=sum(r.input_tokens for r in records),
        cached_tokens=sum(r.cached_tokens for r in records),
        output_tokens=sum(r.output_tokens for r in records),
        failed_trials=failed,
    )


def systems(
    records: Iterable[TrialRecord],
    tasks: Sequence[TaskSpec] | None = None,
    allow_privileged: bool = False,
    allow_partial: bool = False,
) -> dict[str, tuple[IndexResult, Resources]]:
    """``{system: (index result, resources)}``: each task's score is the mean reward of its trials
    (a failed trial counts 0), in order of first appearance of the system.

    Raises:
        RleError: A trial names a task the registry does not know (``index.unknown_task``).
    """
    by_system: dict[str, list[TrialRecord]] = {}
    for r in records:
        by_system.setdefault(r.system, []).append(r)
    out = {}
    for system, trials in by_system.items():
        per_task: dict[str, list[Fraction]] = {}
        privileged = {r.task_id for r in trials if r.privileged}
        partial = {r.task_id for r in trials if r.partial}
        for r in trials:
            per_task.setdefault(r.task_id, []).append(Fraction(r.reward or 0.0))
        reports = [
            {
                "task_id": tid,
                "score": float(sum(v) / len(v)),
                "errors": [{"code": "ledger.privileged", "message": "a trial's session was privileged"}]
                if tid in privileged
                else [],
                "partial": tid in partial,
            }
            for tid, v in per_task.items()
        ]
        result = compute_index(
            reports, name=system, tasks=tasks, allow_privileged=allow_privileged, allow_partial=allow_partial
        )
        measured: dict[str, list[dict[str, float]]] = {}
        for r in trials:
            if r.diagnostics:
                measured.setdefault(r.task_id, []).append(r.diagnostics)
        developed: dict[str, list[Progress]] = {}
        for r in trials:
            p = progress(r.trial, r.development, r.reward)
            if p is not None:
                developed.setdefault(r.task_id, []).append(p)
        result = replace(
            result,
            diagnostics={tid: mean_of(rows) for tid, rows in measured.items()},
            development={tid: tuple(ps) for tid, ps in developed.items()},
        )
        out[system] = (result, resources(trials))
    return out


def format_resources(rows: dict[str, Resources]) -> str:
    """The resources table as plain text (the paper's columns; tokens in millions)."""
    head = (
        f"{'system':<32}{'mean $':>9}{'total $':>10}{'coverage':>10}{'mean h':>8}{'input M':>9}{'cached M':>9}"
        f"{'output M':>9}{'tasks':>7}{'failed':>7}"
    )
    lines = [
        "Resources (means through the task -> family -> workflow hierarchy; totals over trials; coverage: "
        "trials with a reported cost)",
        head,
    ]
    for name, r in rows.items():
        lines.append(
            f"{name[:31]:<32}{r.mean_cost_usd:>9.2f}{r.total_cost_usd:>10.2f}{f'{r.cost_runs}/{r.trials}':>10}"
            f"{r.mean_elapsed_h:>8.2f}{r.input_tokens / 1e6:>9.2f}{r.cached_tokens / 1e6:>9.2f}"
            f"{r.output_tokens / 1e6:>9.2f}{r.tasks:>7}{r.failed:>7}"
        )
    for name, r in rows.items():
        for entry in r.failed_trials:
            lines.append(f"failed ({name}): {entry}")
    return "\n".join(lines)


def resources_html(rows: dict[str, Resources]) -> str:
    """The resources table (the paper's columns) and the failed-trial list as HTML."""
    from html import escape

    cells = "".join(
        f"<tr><td>{escape(name)}</td><td>{r.mean_cost_usd:.2f}</td><td>{r.total_cost_usd:.2f}</td>"
        f"<td>{r.cost_runs}/{r.trials}</td><td>{r.mean_elapsed_h:.2f}</td><td>{r.input_tokens / 1e6:.2f}</td>"
        f"<td>{r.cached_tokens / 1e6:.2f}</td><td>{r.output_tokens / 1e6:.2f}</td><td>{r.tasks}</td>"
        f"<td>{r.failed}</td></tr>"
        for name, r in rows.items()
    )
    failed = "".join(
        f"<li>{escape(name)}: {escape(entry)}</li>" for name, r in rows.items() for entry in r.failed_trials
    )
    return (
        "<table><tr><th>system</th><th>mean $</th><th>total $</th><th>coverage</th><th>mean h</th>"
        "<th>input M</th><th>cached M</th><th>output M</th><th>tasks</th><th>failed (scored 0)</th></tr>"
        f"{cells}</table><p>Costs in USD, elapsed time in hours, tokens in millions. Mean cost and elapsed "
        "time follow the RLE Index's task, family, workflow hierarchy; totals sum every trial; coverage counts "
        "the trials whose agent reported a cost; elapsed time is a trial's start to finish.</p>"
        f"<h3>Failed trials</h3><ul>{failed or '<li>none</li>'}</ul>"
    )


def resources_section(results: Sequence[IndexResult], rows: dict[str, Resources]) -> str:
    """The index page's section for Harbor jobs: performance versus cost, resources, failed trials."""
    return (
        "<h2>Performance versus cost</h2>"
        f'<img alt="performance versus cost" src="data:image/png;base64,{cost_figure(results, rows)}">'
        f"<h2>Resources</h2>{resources_html(rows)}"
    )


def cost_figure(results: Sequence[IndexResult], rows: dict[str, Resources]) -> str:
    """RLE Index [%] against mean cost per trial [USD], one point per system, as a base64 PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rle_tasks.core.results_page import png

    fig, ax = plt.subplots(figsize=(6, 4))
    for r in results:
        cost = rows[r.name].mean_cost_usd if r.name in rows else 0.0
        ax.scatter([cost], [100 * r.index], s=40)
        ax.annotate(r.name, (cost, 100 * r.index), textcoords="offset points", xytext=(5, 5), fontsize=8)
    ax.set_xlabel("mean cost [USD] (task, family, workflow hierarchy)")
    ax.set_ylabel("RLE Index [%]")
    ax.set_ylim(0, 105)
    ax.set_xlim(left=0)
    ax.set_title("Performance versus cost")
    ax.grid(alpha=0.3)
    return png(fig)
