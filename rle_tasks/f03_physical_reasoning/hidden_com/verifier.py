"""Verifier of ``03-hidden-com``: the answers recorded in the sealed session ledger.

Protocol:

1. ``ledger.jsonl`` in the submission must be a sealed, authentic ledger of this task under the
   ledger key of the verifier secret, of a session its server limited to the card's hour
   (``constants.HIDDEN_COM_WALL_TIME_S``); otherwise score 0 with the verdict's reason.
2. The instance is drawn from the secret (``HiddenComInstance.draw``) and the ledger replayed on its
   environment; a ledger of another scene or one that diverges scores 0 with the replay's code.
3. Each box's answer is the first valid answer action of the session given within 12,000 charged
   steps of the previous accepted answer or the start (``env``); a box without one
   counts as wrong, and late answers are reported. Score: the fraction of the three answers that name the ballast's
   quadrant. Only the number correct is reported, never which boxes or the right quadrants.
"""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.runtime.secrets import Secret, derive_rng
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext

from ..constants import HIDDEN_COM_ID, HIDDEN_COM_STEPS, HIDDEN_COM_WALL_TIME_S, N_BOXES, STEPS_PER_BOX
from ..session import LEDGER_FILE, invalid_report, open_ledger, replay_ledger, tabletop_limits
from .env import INVALID, LATE, HiddenComInstance, make_env, recorded_answers
from .scoring import RUBRIC

__all__ = ["LEDGER_FILE", "instance", "verify"]


def instance(secret: Secret) -> HiddenComInstance:
    """The instance of a secret."""
    return HiddenComInstance.draw(derive_rng(secret, HIDDEN_COM_ID, "instance"))


def verify(root: Path, ctx: VerifyContext) -> VerifierReport:
    """Verify a submission directory holding the session's ``ledger.jsonl`` (module docstring)."""
    findings = Findings()
    limits = tabletop_limits(HIDDEN_COM_STEPS, HIDDEN_COM_WALL_TIME_S)
    opened = open_ledger(root, ctx.secret, HIDDEN_COM_ID, limits, ctx.attempt)
    inst = instance(opened.secret)
    gate = replay_ledger(opened, make_env(inst, image_size=None))
    if not gate.ok:
        return invalid_report(RUBRIC, gate.code, gate.message, findings)
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
