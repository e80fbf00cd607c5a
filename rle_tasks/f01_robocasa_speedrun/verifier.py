"""Verifier of the family: the evaluation trials of the sealed ledger, re-executed in the target kitchens.

Protocol:

1. ``ledger.jsonl`` must be a regular file holding a sealed, authentic ledger of this task under the
   ledger key of the verifier secret (``rle_design.ledger.verify_ledger``); otherwise score 0 with the
   verdict's code (``ledger.missing``, ``ledger.unsealed``, ``ledger.altered`` ...).
2. The session must have been served as the task's: its open record names this task's scene set, a
   development budget of 50,000 steps, the card's evaluation phase (5 trials, 1,000 actions, 1 h) and
   a wall-time limit of at most 8 h (``f01.wrong_session`` otherwise).
3. ``d`` is the charged steps before the first evaluation reset. Each evaluation trial is rebuilt from
   the secret and its recorded actions re-executed (``rle_design.ledger.replay_trials``); a trial
   succeeds when the task's success predicate held after one of its actions. The verifier's replay
   decides, not the session's account in the seal (a disagreement is reported as
   ``f01.success_mismatch``); a trial whose scene or actions do not replay makes the ledger
   unverifiable (score 0, ``replay.*``). Missing trials count as failures.
4. R = s [0.80 + 0.20 (1 - d / 50,000)] with s = successes / 5.
"""

from __future__ import annotations

from pathlib import Path

from rle_design.control.replay import ReplayError
from rle_design.ledger import development_steps, replay_trials, verify_ledger
from rle_tasks.core.devenv import ledger_key
from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext

from .scoring import rubric
from .task import ACTIONS_PER_TRIAL, BUDGET, EVAL_WALL_S, STEP_BUDGET, TRIALS, KitchenTaskId, scenes

LEDGER_FILE = "ledger.jsonl"


def _invalid(task_id: str, code: str, message: str, findings: Findings, **native) -> VerifierReport:
    findings.add_error(code, message, LEDGER_FILE)
    zero = Outcome({"trials": 0.0}, f"no verifiable session: {message}")
    return rubric(task_id).report(
        {"success": zero, "efficiency": zero},
        valid=False,
        errors=findings.errors,
        native_metrics={"ledger": code, **native},
    )


def _session_problem(opened: dict, expected_set: str) -> str | None:
    evaluation = opened.get("evaluation") or {}
    limit = opened.get("wall_time_s")
    if opened.get("scene_set") != expected_set:
        return "the ledger was not recorded in this task's kitchen session (its scene set differs)"
    if opened.get("budget") != STEP_BUDGET:
        return f"the session's development budget was {opened.get('budget')!r} steps, the task's is {STEP_BUDGET}"
    if (
        evaluation.get("trials") != TRIALS
        or evaluation.get("actions_per_trial") != ACTIONS_PER_TRIAL
        or evaluation.get("wall_time_s") != EVAL_WALL_S
    ):
        return f"the session's evaluation phase was {evaluation}, the task's is {TRIALS} trials of {ACTIONS_PER_TRIAL} actions in {EVAL_WALL_S:.0f} s"
    if not (isinstance(limit, (int, float)) and 0 < limit <= BUDGET.wall_time_s):
        return (
            f"the session was limited to {limit!r} s of wall time, the task allows {BUDGET.wall_time_s:.0f} s"
        )
    return None


def _render_trials(trials, scene_set, path: Path) -> None:
    """One PNG: the final state of every replayed trial, seen from behind the robot, with its outcome."""
    import numpy as np
    from PIL import Image, ImageDraw

    from rle_design.scene.mobile_panda import HIDDEN_GROUP
    from rle_design.viz.render import render_image

    tiles = []
    for t in trials:
        env = scene_set.scene(t.scene)
        fixture = env.scene.fixtures[env.scene.episode.target["fixture"]]
        look = np.array([fixture.pos[0], fixture.front_y - 0.3, 1.0])
        img = Image.fromarray(
            render_image(
                t.model,
                t.data,
                width=360,
                height=270,
                lookat=look,
                distance=2.6,
                azimuth=90.0,
                elevation=-25.0,
                groups=(HIDDEN_GROUP,),
                sites=False,
            )
        )
        label = f"trial {t.trial}: " + (
            f"success after {t.success_at} actions" if t.success else f"failed ({t.actions} actions)"
        )
        ImageDraw.Draw(img).text((8, 6), label, fill=(0, 120, 0) if t.success else (180, 0, 0))
        tiles.append(img)
    sheet = Image.new("RGB", (360 * len(tiles), 270), "white")
    for i, tile in enumerate(tiles):
        sheet.paste(tile, (360 * i, 0))
    path.parent.mkdir(parents=True, exist_ok=True)
    sheet.save(path)


def verifier(kitchen: KitchenTaskId, level: int):
    """The verify function of one task (``kitchen`` at harness ``level``)."""
    task_id = kitchen.task_id(level)

    def verify(root: Path, ctx: VerifyContext) -> VerifierReport:
        findings = Findings()
        path = Path(root) / LEDGER_FILE
        if path.is_symlink() or not path.is_file():
            return _invalid(
                task_id, "ledger.missing", f"{LEDGER_FILE} is missing or not a regular file", findings
            )
        verdict = verify_ledger(path, ledger_key(ctx.secret, task_id), task_id)
        if not verdict.valid:
            return _invalid(task_id, verdict.code, verdict.message, findings)
        scene_set = scenes(kitchen, level, ctx.secret, image_size=None)
        problem = _session_problem(verdict.opened, scene_set.fingerprint())
        if problem:
            return _invalid(task_id, "f01.wrong_session", problem, findings)
        d = development_steps(path)
        try:
            trials = replay_trials(scene_set, path)
        except ReplayError as exc:
            return _invalid(task_id, exc.code, exc.message, findings, development_steps=d)
        for t in trials:
            if t.recorded_success is not None and t.recorded_success != t.success:
                findings.add_error(
                    "f01.success_mismatch",
                    f"trial {t.trial}: the session recorded success={t.recorded_success}, the replay finds {t.success}",
                    LEDGER_FILE,
                )
        if ctx.out_dir is not None and trials:
            _render_trials(trials, scene_set, Path(ctx.out_dir) / "trials.png")
        wins = sum(t.success for t in trials)
        s = wins / TRIALS
        eff = s * max(0.0, 1.0 - d / STEP_BUDGET)
        per_trial = [
            {"trial": t.trial, "success": t.success, "actions": t.actions, "success_at": t.success_at}
            for t in trials
        ]
        missing = TRIALS - len(trials)
        msg = f"{wins} of {TRIALS} trials succeeded" + (f" ({missing} not played)" if missing else "")
        measured = {"successes": wins, "trials_played": len(trials), "trials": per_trial}
        return rubric(task_id).report(
            {
                "success": Outcome({"trials": s}, msg, measured),
                "efficiency": Outcome(
                    {"trials": eff},
                    f"s (1 - d/{STEP_BUDGET}) with d = {d} development steps",
                    {"development_steps": d},
                ),
            },
            valid=True,
            errors=findings.errors,
            native_metrics={
                "s": s,
                "development_steps": d,
                "successes": wins,
                "trials": per_trial,
                "steps": verdict.steps,
                "level": level,
            },
        )

    return verify
