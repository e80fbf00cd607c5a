"""Verifier of ``03-hidden-com``: the answers recorded in the sealed session ledger.

Protocol:

1. ``ledger.jsonl`` in the submission must be a sealed, authentic ledger of this task under the
   ledger key of the verifier secret; otherwise score 0 (cap ``ledger``) with the verdict's reason.
2. The instance is drawn from the secret (``HiddenComInstance.draw``) and the ledger replayed on its
   environment; a ledger of another scene or one that diverges scores 0 with the replay's code.
3. Each box's answer is the first valid answer action of the session (``hidden_com_env``); a box
   without one counts as wrong. Score: the fraction of the three answers that name the ballast's
   quadrant. Only the number correct is reported, never which boxes or the right quadrants.
"""

from __future__ import annotations

from pathlib import Path

from rle_design.control import ReplayError, replay
from rle_design.ledger import verify_ledger
from rle_tasks.core.devenv import ledger_key
from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.scoring import CheckpointSpec, Fraction, Outcome, Rubric
from rle_tasks.core.secrets import Secret, derive_rng
from rle_tasks.core.task import VerifyContext

from .hidden_com_env import INVALID, N_BOXES, TASK_ID, HiddenComInstance, make_env, recorded_answers

LEDGER_FILE = "ledger.jsonl"

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
    path = Path(root) / LEDGER_FILE
    if path.is_symlink() or (path.exists() and not path.is_file()):
        return _invalid("ledger.missing", f"{LEDGER_FILE} is not a regular file", findings)
    verdict = verify_ledger(path, ledger_key(ctx.secret, TASK_ID), TASK_ID)
    if not verdict.valid:
        return _invalid(verdict.code, verdict.message, findings)
    inst = instance(ctx.secret)
    try:
        _, data, n_actions = replay(make_env(inst, image_size=None), path)
    except ReplayError as exc:
        return _invalid(exc.code, exc.message, findings)
    answers = recorded_answers(data)
    correct = sum(a == q for a, q in zip(answers, inst.quadrants))
    given = sum(a is not None for a in answers)
    message = f"{correct} of {N_BOXES} answers correct ({given} given)"
    measured = {"correct": correct, "answered": given, "ignored_answer_actions": int(data.userdata[INVALID])}
    return RUBRIC.report(
        {"answers": Outcome({"boxes": correct / N_BOXES}, message, measured)},
        valid=True,
        errors=findings.errors,
        native_metrics={"steps": verdict.steps, "actions": n_actions, **measured},
    )
