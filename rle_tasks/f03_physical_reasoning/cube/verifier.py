"""Verifier of ``03-pocket-cube``: the sealed session ledger, replayed, its turns recounted, the end scored.

Protocol:

1. ``ledger.jsonl`` in the submission must be a sealed, authentic ledger of this task under the ledger
   key of the verifier secret (``verify_ledger``); otherwise score 0 with the verdict's code and reason.
2. The scramble is drawn from the secret (``scene.instance``) and the ledger's resets and actions
   replayed on its environment (``rle_design.control.replay``); another scene or a diverging replay
   scores 0 with the replay's code. Along the replay the cube is read every ``env.SAMPLE_EVERY``
   physics steps (10 ms) and once at the end.
3. A reset after the start abandons the attempt (card): score 0.
4. The settled-state sequence of those readings is classified (``turns.transitions``): quarter turns,
   half turns (2), unclassified transitions.
5. The end state must be solved (``final_check``): all faces uniform, every cubie within
   ``reading.ALIGNED_TOL`` of the lattice, every cubie centre slower than ``reading.STILL_SPEED``, and
   the cube **held above its supports**: its lowest corner at least ``reading.LIFT_CLEARANCE`` above
   the stand's top (the highest surface it can rest on; a cube on its stand or on the table is not
   held).
6. Reward (``score.cube_reward``): 0 when the session's turn counter (``cube_session.turns``, counted
   by the server after every action) differs from the recount of step 4 (invalid counters), 0 when not
   solved, else ``min(1, opt / turns)`` with ``opt`` the scramble's optimal quarter-turn count
   (distance table); capped at 0.5 when any transition is unclassified.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rle_design.control import ReplayError, replay
from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.scoring import Cap, CheckpointSpec, Fraction, Outcome, Rubric
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning.cube import env as ce
from rle_tasks.f03_physical_reasoning.cube.reading import (
    ALIGNED_TOL,
    LIFT_CLEARANCE,
    STILL_SPEED,
    CubePoses,
    SolvedCheck,
    lowest_corner,
    poses_from_data,
    read,
)
from rle_tasks.f03_physical_reasoning.cube.scene import STAND_TOP_Z, TABLE, TASK_ID, instance
from rle_tasks.f03_physical_reasoning.cube.score import UNCLASSIFIED_CAP, cube_reward
from rle_tasks.f03_physical_reasoning.cube.turns import transitions

__all__ = ["LEDGER_FILE", "RUBRIC", "final_check", "verify"]

LEDGER_FILE = "ledger.jsonl"

RUBRIC = Rubric(
    task_id=TASK_ID,
    family="03",
    workflow="interactive_control",
    variants=("attempt",),
    checkpoints=(
        CheckpointSpec(
            "solve",
            1.0,
            "solved cube held still above the table at the end of the one attempt; turns = quarter turns "
            "recounted from the replay (a half turn counts 2), opt = the scramble's optimal quarter turns",
            Fraction("0 unless solved with valid counters and no reset; then min(1, opt/turns)"),
        ),
    ),
    caps=(
        Cap(
            "unclassified",
            UNCLASSIFIED_CAP,
            "a change between settled cube states is not one quarter or half turn of a single layer",
        ),
    ),
)


def final_check(poses: CubePoses) -> SolvedCheck:
    """The solved predicate at the end of the attempt, every failing condition named in the reason."""
    reading = read(poses)
    low = lowest_corner(poses)
    speed = float(np.max(poses.cubie_speed))
    measured = {
        "misalignment_deg": math.degrees(reading.misalignment),
        "lowest_corner_above_stand_top": low - STAND_TOP_Z,
        "lowest_corner_above_table": low - TABLE.top_z,
        "max_cubie_speed": speed,
    }
    if not all(math.isfinite(v) for v in measured.values()):
        return SolvedCheck(False, "cube poses are not finite", measured)
    failed = []
    if not reading.state.is_valid():
        failed.append("cube broken: two cubies read in the same slot")
    elif not reading.state.is_solved():
        failed.append("faces are not uniform: " + reading.state.facelets())
    if reading.misalignment > ALIGNED_TOL:
        failed.append(
            f"a layer is {measured['misalignment_deg']:.1f} deg off the lattice (> {math.degrees(ALIGNED_TOL):.0f})"
        )
    if speed > STILL_SPEED:
        failed.append(f"cube moving at {speed:.3f} m/s (> {STILL_SPEED})")
    if low - STAND_TOP_Z < LIFT_CLEARANCE:
        where = "on the table" if low - TABLE.top_z < LIFT_CLEARANCE else "on or beside its stand"
        failed.append(
            f"cube not held above the table: it rests {where} (lowest corner "
            f"{1000 * (low - STAND_TOP_Z):.1f} mm above the stand top, < {1000 * LIFT_CLEARANCE:.0f})"
        )
    return SolvedCheck(not failed, "; ".join(failed), measured)


def _invalid(code: str, message: str, findings: Findings) -> VerifierReport:
    findings.add_error(code, message, LEDGER_FILE)
    return RUBRIC.report(
        {"solve": Outcome({"attempt": 0.0}, f"no valid session: {message}")},
        valid=False,
        errors=findings.errors,
        native_metrics={"ledger": code},
    )


def verify(root: Path, ctx: VerifyContext) -> VerifierReport:
    """Verify a submission directory holding the session's ``ledger.jsonl`` (module docstring)."""
    from ..session import note_privileged, open_ledger, tabletop_limits
    from .scene import BUDGET_STEPS, WALL_TIME_S

    findings = Findings()
    opened = open_ledger(root, ctx.secret, TASK_ID, tabletop_limits(BUDGET_STEPS, WALL_TIME_S), ctx.attempt)
    if not opened.ok:
        return _invalid(opened.code, opened.message, findings)
    privileged = note_privileged(opened, findings)
    inst = instance(opened.secret)
    readings: list = []
    try:
        model, data, n_actions = replay(ce.make_env(inst, image_size=None, recorder=readings), opened.path)
    except ReplayError as exc:
        return _invalid(exc.code, exc.message, findings)
    readings.append(ce.cube_reading(model, data))
    session = ce.counters(model, data)
    native = {
        "steps": opened.gate.steps,
        "actions": n_actions,
        "optimal": inst.optimal,
        "attempt": opened.attempt,
        "privileged_session": privileged,
        **session,
    }
    if session["attempt_void"]:
        message = f"attempt abandoned: {int(data.userdata[ce.VOID])} reset(s) after the start"
        return RUBRIC.report(
            {"solve": Outcome({"attempt": 0.0}, message, session)},
            valid=True,
            errors=findings.errors,
            native_metrics=native,
        )
    trans = transitions(readings)
    check = final_check(poses_from_data(model, data))
    score = cube_reward(
        solved=check.solved, optimal=inst.optimal, ledger_turns=session["turns"], transitions=trans
    )
    message = score.reason if check.solved else f"{score.reason} ({check.reason})"
    measured = {
        "turns": score.turns,
        "optimal": score.optimal,
        "unclassified": score.unclassified,
        "session_turns": session["turns"],
        "rescues": session["rescues"],
        "moves": [t.move for t in trans],
        "solved": check.solved,
        **check.measured,
    }
    return RUBRIC.report(
        {"solve": Outcome({"attempt": score.reward}, message, measured)},
        valid=True,
        errors=findings.errors,
        caps=("unclassified",) if score.unclassified else (),
        native_metrics={**native, "turns": score.turns, "unclassified": score.unclassified},
    )
