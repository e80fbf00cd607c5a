"""Verifier of the family: the evaluation trials of the sealed ledger, re-executed in the target kitchens.

Protocol:

1. ``ledger.jsonl`` passes the ledger gate (``rle_design.ledger.check_ledger``) under the ledger key
   of the verifier secret: a regular file holding a sealed, authentic ledger of this task, of the
   attempt being verified (``ctx.attempt``; unbound when None), served with the card's limits, and
   within them on its own records: at most 50,000 development steps, at most 5 evaluation trials of
   at most 1,000 actions, every step charged within the session's 8 h and the evaluation phase's
   1 h, the seal's counts equal to the records'. Otherwise score 0 with the gate's code
   (``ledger.altered``, ``ledger.over_budget``, ``ledger.trial_too_long``, ``ledger.wrong_attempt`` ...).
2. The session must have been served as this task's: its open record names this task's scene set
   (``f01.wrong_session`` otherwise).
3. ``d`` is the charged steps before the first evaluation reset. Each evaluation trial is rebuilt from
   the secret bound to the ledger's attempt and its recorded actions re-executed
   (``rle_design.ledger.replay_trials``); a trial succeeds when the task's success predicate held
   after one of its actions. The verifier's replay decides; where the seal's account differs, the
   trial counts as failed (``ledger.seal_mismatch``). A trial whose scene or actions do not replay
   makes the ledger unverifiable (score 0, ``replay.*``, ``ledger.action_out_of_range``). Missing
   trials count as failures.
4. R = s [0.80 + 0.20 (1 - d / 50,000)] with s = successes / 5.
"""

from __future__ import annotations

import math
from pathlib import Path

from rle_design.control.replay import ReplayError
from rle_design.ledger import Limits, check_ledger, replay_trials
from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.runtime.devenv import ledger_key
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext

from .constants import ACTIONS_PER_TRIAL, EVAL_WALL_S, STEP_BUDGET, TRIALS, WALL_TIME_S
from .kitchens import kitchen_level, scenes
from .scoring import rubric

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


LIMITS = Limits(
    budget=STEP_BUDGET,
    wall_time_s=WALL_TIME_S,
    trials=TRIALS,
    actions_per_trial=ACTIONS_PER_TRIAL,
    evaluation_wall_time_s=EVAL_WALL_S,
)
"""The card's limits, re-checked on every submitted ledger."""


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
        (fx, fy), (nx, ny) = fixture.front, fixture.facing
        look = np.array([fx + 0.3 * nx, fy + 0.3 * ny, 1.0])
        img = Image.fromarray(
            render_image(
                t.model,
                t.data,
                width=360,
                height=270,
                lookat=look,
                distance=2.6,
                azimuth=90.0 + math.degrees(fixture.yaw),  # looking at the front
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


def verify(root: Path, ctx: VerifyContext, *, task_id: str) -> VerifierReport:
    """Score the sealed session at ``root`` for ``task_id`` (a kitchen task at a harness level; module
    docstring)."""
    kitchen, level = kitchen_level(task_id)
    findings = Findings()
    path = Path(root) / LEDGER_FILE
    if path.is_symlink() or not path.is_file():
        return _invalid(
            task_id, "ledger.missing", f"{LEDGER_FILE} is missing or not a regular file", findings
        )
    gate = check_ledger(path, ledger_key(ctx.secret, task_id), task_id, LIMITS, ctx.attempt)
    if not gate.ok:
        return _invalid(task_id, gate.code, gate.message, findings)
    attempt = {"id": gate.attempt, "bound": gate.attempt_bound}
    scene_set = scenes(kitchen, level, ctx.secret.for_attempt(gate.attempt), image_size=None)
    if gate.opened.get("scene_set") != scene_set.fingerprint():
        return _invalid(
            task_id,
            "f01.wrong_session",
            "the ledger was not recorded in this task's kitchen session (its scene set differs)",
            findings,
        )
    d = gate.development_steps
    try:
        trials = replay_trials(scene_set, path)
    except ReplayError as exc:
        return _invalid(task_id, exc.code, exc.message, findings, development_steps=d)
    disputed = set()
    for t in trials:
        if t.recorded_success is not None and t.recorded_success != t.success:
            disputed.add(t.trial)
            findings.add_error(
                "ledger.seal_mismatch",
                f"trial {t.trial}: the seal records success={t.recorded_success}, the replay finds {t.success}; "
                "the trial counts as failed",
                LEDGER_FILE,
            )
    if ctx.out_dir is not None and trials:
        _render_trials(trials, scene_set, Path(ctx.out_dir) / "trials.png")
    wins = sum(t.success and t.trial not in disputed for t in trials)
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
            "steps": gate.steps,
            "level": level,
            "attempt": attempt,
        },
    )
