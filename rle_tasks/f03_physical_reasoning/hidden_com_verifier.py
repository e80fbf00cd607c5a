"""Verifier of ``03-hidden-com``: the answers recorded in the sealed session ledger.

Protocol:

1. ``ledger.jsonl`` in the submission must be a sealed, authentic ledger of this task under the
   ledger key of the verifier secret, of a session its server limited to the card's hour
   (``WALL_TIME_S``); otherwise score 0 with the verdict's reason.
2. The instance is drawn from the secret (``HiddenComInstance.draw``) and the ledger replayed on its
   environment; a ledger of another scene or one that diverges scores 0 with the replay's code.
3. Each box's answer is the first valid answer action of the session given within 12,000 charged
   steps of the previous accepted answer or the start (``hidden_com_env``); a box without one
   counts as wrong, and late answers are reported. Score: the fraction of the three answers that name the ballast's
   quadrant. Only the number correct is reported, never which boxes or the right quadrants.
"""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.scoring import CheckpointSpec, Fraction, Outcome, Rubric
from rle_tasks.core.secrets import Secret, derive_rng
from rle_tasks.core.task import VerifyContext

from .hidden_com_env import (
    INVALID,
    LATE,
    N_BOXES,
    STEPS_PER_BOX,
    TASK_ID,
    HiddenComInstance,
    make_env,
    recorded_answers,
)
from .hidden_com_scene import BUDGET_STEPS, WALL_TIME_S
from .session import LEDGER_FILE, open_ledger, replay_ledger, tabletop_limits

RUBRIC = Rubric(
    task_id=TASK_ID,
    family="03",
    workflow="interactive_control",
    variants=("boxes",),
    checkpoints=(
        CheckpointSpec(
            "answers",
            1.0,
            "answers naming the ballast quadrant, out of three boxes (first valid answer per box)",
            Fraction("fraction of the three answers correct"),
        ),
    ),
)


def instance(secret: Secret) -> HiddenComInstance:
    """The instance of a secret."""
    return HiddenComInstance.draw(derive_rng(secret, TASK_ID, "instance"))


def _invalid(code: str, message: str, findings: Findings) -> VerifierReport:
    findings.add_error(code, message, LEDGER_FILE)
    return RUBRIC.report(
        {"answers": Outcome({"boxes": 0.0}, f"no valid session: {message}")},
        valid=False,
        errors=findings.errors,
        native_metrics={"ledger": code},
    )


def verify(root: Path, ctx: VerifyContext) -> VerifierReport:
    """Verify a submission directory holding the session's ``ledger.jsonl`` (module docstring)."""

    findings = Findings()
    opened = open_ledger(root, ctx.secret, TASK_ID, tabletop_limits(BUDGET_STEPS, WALL_TIME_S), ctx.attempt)
    inst = instance(opened.secret)
    gate = replay_ledger(opened, make_env(inst, image_size=None))
    if not gate.ok:
        return _invalid(gate.code, gate.message, findings)
    data = gate.data
    answers = recorded_answers(data)
    correct = sum(a == q for a, q in zip(answers, inst.quadrants))
    given = sum(a is not None for a in answers)
    late = int(data.userdata[LATE])
    message = f"{correct} of {N_BOXES} answers correct ({given} given)"
    if late:
        message += (
            f"; {late} answer action(s) refused as late (more than {STEPS_PER_BOX} steps after the previous)"
        )
    measured = {
        "correct": correct,
        "answered": given,
        "ignored_answer_actions": int(data.userdata[INVALID]),
        "late_answer_actions": late,
    }
    native = {
        "steps": gate.steps,
        "actions": gate.actions,
        "elapsed_s": gate.elapsed_s,
        "attempt": gate.attempt,
        **measured,
    }
    return RUBRIC.report(
        {"answers": Outcome({"boxes": correct / N_BOXES}, message, measured)},
        valid=True,
        errors=findings.errors,
        native_metrics=native,
    )
