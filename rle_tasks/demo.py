"""``rle demo``: the main job. Verifies every shipped solution of every implemented task, computes the
RLE Index of the reference solutions, renders the canonical arms, and writes ``out/demo/index.html``.

``rle demo`` (``make demo``) verifies every solution in quick mode (each task's reduction is its
``quick_note``, printed on the page), and family 05 evaluates the checkpoint an earlier training of the
same recipe on the same data left in this machine's cache, or the reference's shipped checkpoint pinned
to that recipe and data (``f05_nanovla.training``), instead of training again
(``VerifyContext.reuse_training``); its RLE Index marks the partial scores. ``rle demo --full``
(``make demo-full``) is the complete run: references in full, baselines quick unless ``full_baselines``,
every recipe retrained (the report says whether the checkpoint reproduced the cached one), and the
solutions that exist to run out a long time limit. The page marks every report's mode. A report made in quick mode with the public development key
is compared with the solution's golden score (``Solution.quick_score``): a difference is printed and
marked on the page, because it means this machine or this checkout does not reproduce the pinned result
(a recipe whose training stopped early on a loaded machine, for example).
"""

from __future__ import annotations

import html
import json
import time
from collections.abc import Sequence
from pathlib import Path

from tqdm import tqdm

from rle_design.errors import RleError
from rle_tasks.core.registry import all_tasks
from rle_tasks.core.report import VerifierReport
from rle_tasks.core.runtime.secrets import load_secret
from rle_tasks.core.solutions import declaration, materialise
from rle_tasks.core.task import TaskSpec, VerifyContext
from rle_tasks.core.verify import VerifierSetupError, run_verify
from rle_tasks.demo_checks import full_scores, golden_differences, retrainings, unpinned_full
from rle_tasks.demo_progress import Estimate

TEST_BASE = Path(__file__).parent / "demo_assets" / "test_base.xml"


def render_arms(out: Path) -> list[Path]:
    """PNG of each canonical arm on the demo test base (front, side, iso views)."""
    from rle_design.scene import arm_ids
    from rle_design.viz.preview import preview

    return [
        Path(preview(TEST_BASE, arm=arm, png=out / "arms" / f"{arm}.png", mount_site="arm_mount_site"))
        for arm in arm_ids()
    ]


def _mode(name: str, quick: bool, full_baselines: bool, episode_scored: bool = False) -> bool:
    """True where the solution ``name`` is verified with the reduced batteries (always for a task
    scored over a fixed episode set: its full set is hours of simulation, its quick run is marked
    partial)."""
    return quick or episode_scored or (name != "reference" and not full_baselines)


def select_tasks(patterns: Sequence[str] | None) -> list[TaskSpec]:
    """The implemented tasks named by ``patterns`` (task ids, or family numbers such as ``05``), in
    registry order; every implemented task when ``patterns`` is empty.

    Raises:
        RleError: ``demo.unknown_task`` for a pattern that names no implemented task (the message lists
            them).
    """
    implemented = [t for t in all_tasks() if t.implemented]
    if not patterns:
        return implemented
    chosen: set[str] = set()
    for pattern in patterns:
        hits = {
            t.id for t in implemented if t.id == pattern or (pattern.isdigit() and t.family == int(pattern))
        }
        if not hits:
            raise RleError(
                f"'{pattern}' names no implemented task; give a task id or a family number. "
                f"Implemented: {', '.join(t.id for t in implemented)}",
                code="demo.unknown_task",
            )
        chosen |= hits
    return [t for t in implemented if t.id in chosen]


def long_runners(task: TaskSpec) -> dict[str, float]:
    """Solutions of ``task`` that exist to run out a time limit: name -> the limit [s]."""
    if not task.solutions_module or not task.solutions:
        return {}
    decl = declaration(task)
    return {n: decl.get(n).runs_out_s for n in task.solutions if decl.get(n).runs_out_s is not None}


def _verify_all(
    out: Path,
    quick: bool,
    jobs: int,
    full_baselines: bool = False,
    tasks: Sequence[str] | None = None,
    full: bool = False,
) -> list[tuple[str, str, Path, VerifierReport]]:
    runs = []
    not_run.clear()
    for t in select_tasks(tasks):
        waits = {} if full else long_runners(t)
        for name in t.solutions:
            if name in waits:
                not_run.append(
                    (
                        t.id,
                        name,
                        f"runs out its {waits[name]:.0f} s limit by design: `rle demo --full` runs it",
                    )
                )
            else:
                runs.append((t, name))
    secret = load_secret(None)
    results = []
    clock = Estimate(runs, full)
    bar = tqdm(runs, desc="verifying shipped solutions", unit="artifact")
    for task, name in bar:
        bar.set_postfix_str(f"{task.id}:{name} | {clock.left(task.family)}")
        started = time.perf_counter()
        directory = materialise(task, name)
        slug = name.replace("/", "_")
        report_path = out / "reports" / task.id / f"{slug}.json"
        ctx = VerifyContext(
            secret=secret,
            out_dir=report_path.parent / f"{slug}_figures",
            jobs=jobs,
            quick=_mode(name, quick, full_baselines, task.episode_scored),
            reuse_training=not full,
        )
        try:
            report, _ = run_verify(task, directory, ctx)
        except VerifierSetupError as exc:  # the operator's set-up, not the solution: say what to do
            not_run.append((task.id, name, exc.message))
            continue
        report.write(report_path)
        results.append((task.id, name, report_path, report))
        clock.done(task, name, time.perf_counter() - started)
    clock.write(out / "times.json")
    return results


not_run: list[tuple[str, str, str]] = []
"""(task, solution, why) of the solutions the last ``_verify_all`` could not verify here."""


def _figures(report_path: Path) -> list[Path]:
    d = report_path.parent / f"{report_path.stem}_figures"
    return sorted(d.glob("*.png")) if d.is_dir() else []


def write_html(
    out: Path,
    results,
    arm_pngs: list[Path],
    index_html: Path | None,
    elapsed: float,
    modes: dict[tuple[str, str], bool] | None = None,
    differs: dict[tuple[str, str], float] | None = None,
    subset: list[str] | None = None,
    full: bool = True,
) -> Path:
    """Write ``out/index.html``; ``subset`` lists the task ids when the demo ran only some tasks; ``full``:
    the complete run (``rle demo --full``), else the page says what quick mode shortened."""
    rows = []
    modes = modes or {}
    differs = differs or {}
    for task_id, name, path, rep in results:
        mode = "quick" if modes.get((task_id, name)) else "full"
        training = rep.native_metrics.get("training")
        if training in ("reused", "shipped"):
            mode += ", cached training" if training == "reused" else ", shipped checkpoint"
        elif training == "trained":
            same = rep.native_metrics.get("ckpt_reproduced")
            mode += {True: ", retrained: checkpoint reproduced", None: ", trained"}.get(
                same, ", retrained: <span style='color:#b00'>checkpoint differs</span>"
            )
        golden = differs.get((task_id, name))
        note = "" if golden is None else f" <span style='color:#b00'>(golden {golden:.3f})</span>"
        reasons = "; ".join(f"{e.code}" for e in rep.errors[:4])
        failed = ", ".join(c.id for c in rep.checkpoints if not c.passed)
        rows.append(
            f"<tr><td>{html.escape(task_id)}</td><td>{html.escape(name)}</td><td>{mode}</td><td><b>{rep.score:.3f}</b>{note}</td>"
            f"<td>{'' if rep.cap is None else rep.cap}</td><td>{html.escape(failed)}</td>"
            f"<td>{html.escape(reasons)}</td><td><a href='{path.relative_to(out)}'>json</a></td></tr>"
        )
    figs = []
    for task_id, name, why in not_run:
        rows.append(
            f"<tr><td>{html.escape(task_id)}</td><td>{html.escape(name)}</td><td>not run</td><td></td><td></td>"
            f"<td></td><td>{html.escape(why)}</td><td></td></tr>"
        )
    for task_id, name, path, _ in results:
        for png in _figures(path):
            figs.append(
                f"<figure><img src='{png.relative_to(out)}' width='480'><figcaption>{html.escape(task_id)} "
                f"{html.escape(name)}: {html.escape(png.stem)}</figcaption></figure>"
            )
    arms = "".join(
        f"<figure><img src='{p.relative_to(out)}' width='720'><figcaption>{p.stem} on the demo base</figcaption></figure>"
        for p in arm_pngs
    )
    index_link = (
        f"<p><a href='{index_html.relative_to(out)}'>RLE Index of the reference solutions</a></p>"
        if index_html
        else ""
    )
    scope = (
        "Every shipped solution of every implemented task"
        if not subset
        else "The shipped solutions of the selected tasks only ("
        + html.escape(", ".join(subset))
        + "; the RLE Index counts every other task 0)"
    )
    tasks = {t.id: t for t in all_tasks()}
    shown = sorted({task_id for task_id, *_ in results})
    notes = "".join(
        f"<tr><td>{html.escape(t)}</td><td>{html.escape(tasks[t].quick_note)}</td></tr>"
        for t in shown
        if tasks[t].quick_note
    )
    how = (
        "References run the full batteries; baselines run the reduced (quick) batteries unless "
        "<code>rle demo --full-baselines</code>; every recipe is trained."
        if full
        else "Every solution runs in quick mode: the scores are partial (what each task's quick run covers is "
        "listed below; tasks not listed verify the same in both modes). Family 05 evaluates the checkpoint "
        "that an earlier training of the same recipe on the same data left in this machine's cache "
        "(marked <i>cached training</i>), or the reference's shipped checkpoint pinned to that recipe and "
        "data by sha256 (<i>shipped checkpoint</i>), else trains it. <code>make demo-full</code> runs "
        "references in "
        "full, retrains every recipe and runs the solutions that exist to run out a long limit."
    )
    quick_table = (
        f"<h2>What quick mode runs</h2><table><tr><th>task</th><th>quick run</th></tr>{notes}</table>"
        if notes and not full
        else ""
    )
    page = f"""<!doctype html><html><head><meta charset="utf-8"><title>RLE-Bench demo</title>
<style>body{{font-family:sans-serif;margin:2em;max-width:1400px}}table{{border-collapse:collapse}}
td,th{{border:1px solid #ccc;padding:4px 8px;font-size:14px}}figure{{display:inline-block;margin:6px}}</style></head>
<body><h1>RLE-Bench demo</h1><p>{scope}, verified with the public
development key ({elapsed:.0f} s). {how} A quick-mode score that differs from the solution's
pinned golden score is shown in red beside it.</p>{index_link}
<h2>Verifier reports</h2><table><tr><th>task</th><th>solution</th><th>mode</th><th>score</th><th>cap</th>
<th>failed checkpoints</th><th>errors</th><th>report</th></tr>{"".join(rows)}</table>{quick_table}
<h2>Design renders</h2>{"".join(figs) or "<p>(no figures)</p>"}
<h2>Canonical arms</h2>{arms}</body></html>"""
    path = out / "index.html"
    path.write_text(page)
    return path


def run_demo(
    out: Path,
    quick: bool = False,
    jobs: int = 1,
    full_baselines: bool = False,
    tasks: Sequence[str] | None = None,
    full: bool = False,
) -> int:
    """Verify the shipped solutions of ``tasks`` (every implemented task by default), write the page.

    With a subset of the tasks the RLE Index on the page covers only those references (every other
    task counts 0), and the page says so. Solutions that exist to run out a long time limit
    (``Solution.runs_out_s``) are listed, not run, unless ``full``.
    """
    selected = select_tasks(tasks)
    t0 = time.perf_counter()
    out.mkdir(parents=True, exist_ok=True)
    results = _verify_all(out, quick, jobs, full_baselines, tasks, full)
    every = [t for t in all_tasks() if t.implemented]
    subset = (
        "" if len(selected) == len(every) else f" of {len(selected)} of the {len(every)} implemented tasks"
    )
    scored = {t.id for t in all_tasks() if t.episode_scored}
    modes = {(t, n): _mode(n, quick, full_baselines, t in scored) for t, n, _, _ in results}
    index_html = None
    refs = [str(p) for _, name, p, _ in results if name == "reference"]
    if refs:
        from rle_tasks.core.browser import find_browser
        from rle_tasks.core.results import index_command

        index_html = out / "rle_index.html"
        shot = out / "rle_index.png" if find_browser() else None  # a picture of the page, where a browser is
        index_command(
            refs,
            html=str(index_html),
            name="reference solutions" + subset,
            allow_partial=True,
            screenshot=shot,
        )
    print("rendering the canonical arms ...")
    arm_pngs = render_arms(out)
    differs = golden_differences(results, modes)
    page = write_html(
        out,
        results,
        arm_pngs,
        index_html,
        time.perf_counter() - t0,
        modes,
        differs,
        [t.id for t in selected] if subset else None,
        full,
    )
    summary = {f"{t}:{n}": round(r.score, 4) for t, n, _, r in results}
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    if full:  # what pins demo_checks.FULL_GOLDENS when copied there
        (out / "full_scores.json").write_text(json.dumps(full_scores(results, modes), indent=1) + "\n")
    for (t, n, _, _), (key, score) in zip(results, summary.items(), strict=True):
        golden = differs.get((t, n))
        note = "" if golden is None else f"  differs from its golden score {golden:.3f}"
        print(f"  {key:<50} {score:.3f}  ({'quick' if modes[(t, n)] else 'full'}){note}")
    for t, n, why in not_run:
        print(f"  {t}:{n:<{49 - len(t)}} not run: {why}")
    for t, n, same in retrainings(results):
        said = {True: "reproduced", False: "DIFFERS from", None: "nothing to compare with"}[same]
        print(f"  {t}:{n:<{49 - len(t)}} retrained checkpoint: {said} the pinned one")
    unpinned = unpinned_full(results, modes)
    if unpinned:
        print(f"  {len(unpinned)} full-mode report(s) have no pinned full golden score to compare with")
    if differs:
        print(
            f"{len(differs)} score(s) differ from their golden scores: this machine or checkout "
            "does not reproduce the pinned results (see the reports' native metrics)"
        )
    print(f"open {page}")
    return 0
