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
6. Reward (``scoring.cube_reward``): 0 when the session's turn counter (``cube_session.turns``, counted
   by the server after every action) differs from the recount of step 4 (invalid counters), 0 when not
   solved, else ``min(1, opt / turns)`` with ``opt`` the scramble's optimal quarter-turn count
   (distance table); capped at 0.5 when any transition is unclassified.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning.constants import CUBE_ID, STEP_BUDGET, WALL_TIME_S
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
from rle_tasks.f03_physical_reasoning.cube.scene import STAND_TOP_Z, TABLE, instance
from rle_tasks.f03_physical_reasoning.cube.scoring import RUBRIC, cube_reward
from rle_tasks.f03_physical_reasoning.cube.turns import transitions
from rle_tasks.f03_physical_reasoning.session import (
    LEDGER_FILE,
    invalid_report,
    note_privileged,
    open_ledger,
    replay_ledger,
    tabletop_limits,
)

__all__ = ["LEDGER_FILE", "final_check", "verify"]


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


def verify(root: Path, ctx: VerifyContext) -> VerifierReport:
    """Verify a submission directory holding the session's ``ledger.jsonl`` (module docstring)."""
    findings = Findings()
    opened = open_ledger(root, ctx.secret, CUBE_ID, tabletop_limits(STEP_BUDGET, WALL_TIME_S), ctx.attempt)
    if not opened.ok:
        return invalid_report(RUBRIC, opened.code, opened.message, findings)
    privileged = note_privileged(opened, findings)
    inst = instance(opened.secret)
    readings: list = []
    gate = replay_ledger(opened, ce.make_env(inst, image_size=None, recorder=readings))
    if not gate.ok:
        return invalid_report(RUBRIC, gate.code, gate.message, findings)
    model, data, n_actions = gate.model, gate.data, gate.actions
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
