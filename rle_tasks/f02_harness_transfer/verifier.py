"""Verifier of family 02: five fresh agents attempt the held-out task with the submitted harness.

1. ``agent_harness/MANUAL.md`` must exist (the contract); otherwise score 0 with ``f02.no_manual``.
2. Five ``TransferUnit``s (one per fresh agent: an unseen kitchen and episode from the secret, its own
   ledger key) run through the core fan-out (``run_units``) (``ctx.jobs`` workers, local pool or Ray); quick mode runs
   the first two and marks the report ``partial``; its score is then the mean over the agents it ran
   (an estimate of the full score, as family 05's partial episode sets are), never an official score.
3. Score: the mean of the five s_trial (``transfer.stage_score``); a trial that could not be scored
   (no stage records, harness unusable, unverifiable ledger) counts 0. Every agent that did not run to
   its end or left nothing to score is reported: ``f02.<agent ending>`` (``f02.no_entry_point``,
   ``f02.missing_function``, ``f02.sandbox.forbidden`` ...) or ``f02.<status>``
   (``f02.harness_unusable``, ``f02.no_stage_records``, ``f02.no_session``).
"""

from __future__ import annotations

import os
from pathlib import Path

from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.runtime.devenv import ledger_key
from rle_tasks.core.runtime.parallel import run_units
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext

from .constants import AGENT_STEPS, AGENT_WALL_S, TRIALS
from .groups import Group, group_of
from .harness import HARNESS_DIR
from .scoring import rubric
from .transfer import AGENT_ENV, TransferUnit, run_unit, targets

QUICK_TRIALS = 2
"""Fresh agents run in quick mode (tests, the demo's baselines); the report says ``partial``."""


def units(group: Group, root: Path, ctx: VerifyContext) -> list[TransferUnit]:
    """The evaluation units of a submission (``QUICK_TRIALS`` in quick mode)."""
    agent = os.environ.get(AGENT_ENV, "scripted") or "scripted"
    n = QUICK_TRIALS if ctx.quick else TRIALS
    return [
        TransferUnit(
            trial=k,
            task=group.held_out,
            layout_seed=layout,
            episode_seed=episode,
            harness=Path(root) / HARNESS_DIR,
            key=ledger_key(ctx.secret, f"{group.task_id}/agent-{k}"),
            ledger_task=f"{group.task_id}/agent-{k}",
            agent=agent,
            steps=AGENT_STEPS,
            wall_time_s=AGENT_WALL_S,
            out_dir=ctx.out_dir,
        )
        for k, (layout, episode) in enumerate(targets(ctx.secret, group)[:n])
    ]


def verify(root: Path, ctx: VerifyContext, *, task_id: str) -> VerifierReport:
    """Score the harness at ``root`` for the group ``task_id`` (module docstring)."""
    group = group_of(task_id)
    findings = Findings()
    manual = Path(root) / HARNESS_DIR / "MANUAL.md"
    if manual.is_symlink() or not manual.is_file():
        findings.add_error(
            "f02.no_manual",
            f"{HARNESS_DIR}/MANUAL.md is missing: a fresh agent has no manual",
            f"{HARNESS_DIR}/MANUAL.md",
        )
        return rubric(task_id).report(
            {"transfer": Outcome({"agents": 0.0}, "no harness manual")},
            valid=False,
            errors=findings.errors,
            native_metrics={"trials": []},
        )
    todo = units(group, Path(root), ctx)
    results = run_units(run_unit, todo, ctx)
    for r in results:
        if r.status != "scored" or r.agent != "ran":
            findings.add_error(
                f"f02.{r.status}" if r.agent in ("ran", "not_run") else f"f02.{r.agent}",
                f"fresh agent {r.trial}: {r.status}, {r.agent}: {r.message}"[:600],
                HARNESS_DIR,
            )
    ran = max(len(results), 1)
    total = sum(r.score for r in results) / ran
    wins = sum(r.success for r in results)
    msg = f"mean s_trial {total:.3f} over {len(results)} fresh agents ({wins} succeeded; " + ", ".join(
        f"{r.score:.2f}" for r in results
    )
    msg += (
        ")"
        if len(results) == TRIALS
        else f"; partial: {TRIALS - len(results)} of the {TRIALS} not run in quick mode)"
    )
    native = {
        "held_out": group.held_out,
        "successes": wins,
        "success_rate": wins / ran,
        "trials": [r.record() for r in results],
        "partial": len(results) < TRIALS,
    }
    return rubric(task_id).report(
        {"transfer": Outcome({"agents": total}, msg, {"s_trial": [r.score for r in results]})},
        valid=True,
        errors=findings.errors,
        native_metrics=native,
    )
