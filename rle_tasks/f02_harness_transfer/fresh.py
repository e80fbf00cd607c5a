"""One fresh agent as a task of its own, so that an operator's agent can be one in a Harbor trial.

``02-group-NN-fresh-K`` (K = 0..4) is fresh agent K of group NN's transfer evaluation: the workspace
holds only the submitted ``agent_harness/`` (from ``RLE_F02_HARNESS``), the held-out task's
``instruction.md`` and the metered ``client.py`` of one unseen kitchen; 5,000 steps and 1 h. The
session is served like any metered development environment (``rle dev``, or the development sidecar
of an exported task), so the ledger key and the kitchen stay with the server; its ledger is the
artifact. The verifier gates the ledger (this task's key, the card's limits, the attempt) and replays
it as the group verifier does: the reward is that agent's ``s_trial``. ``group_report`` turns the five
rewards into the group's report (``harbor_trials`` runs the five trials).

These tasks are resolved by ``get_task`` (``stage_task``) but are not among the 51: they are the second
stage of a family-02 job, not a task of their own. The kitchens are bound to the session's attempt
(``Secret.for_attempt``): each trial draws its own unseen kitchen from the secret.
"""

from __future__ import annotations

import functools
import os
import re
from pathlib import Path

from rle_design.control.replay import ReplayError
from rle_design.errors import RleError
from rle_design.ledger import Limits, check_ledger
from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.runtime.devenv import ledger_key
from rle_tasks.core.runtime.secrets import Secret, current_secret
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import ArtifactContract, Budget, ImageData, TaskSpec, VerifyContext

from .constants import AGENT_STEPS, AGENT_WALL_S, TRIALS
from .groups import GROUPS, Group
from .harness import FRESH_INSTRUCTION, HARNESS_DIR, HarnessError, copy_harness
from .scoring import fresh_rubric as rubric
from .scoring import rubric as group_rubric
from .transfer import TransferUnit, _env, _stages, stage_score, targets

FRESH_ID = re.compile(r"^(02-group-\d\d)-fresh-(\d)$")
HARNESS_ENV = "RLE_F02_HARNESS"
"""The submitted ``agent_harness/`` directory a fresh agent's workspace is laid out with."""
LIMITS = Limits(AGENT_STEPS, AGENT_WALL_S)

INSTRUCTION = """You are a fresh agent: you have never seen this kitchen or this task. Your workspace
(`/workspace`, or the current directory) holds only:

- `instruction.md`: the task, your budget and what is allowed;
- `agent_harness/`: a harness another agent wrote for tasks like this one (start with
  `agent_harness/MANUAL.md`);
- `client.py`: the metered client of the one kitchen you work in (`from client import connect`).

Do the task in that kitchen with the harness. Every reset and executed action is charged and recorded
in a sealed session outside your reach; the verifier replays that session and credits the task's
stages you reached (1 on success). Nothing needs to be submitted.
"""


def fresh_id(group: Group, trial: int) -> str:
    return f"{group.task_id}-fresh-{trial}"


def _group(task_id: str) -> tuple[Group, int] | None:
    found = FRESH_ID.match(task_id)
    if not found or not 0 <= int(found[2]) < TRIALS:
        return None
    group = next((g for g in GROUPS if g.task_id == found[1]), None)
    return (group, int(found[2])) if group is not None else None


def _unit(group: Group, trial: int, secret: Secret, out_dir: Path | None = None) -> TransferUnit:
    layout, episode = targets(secret, group)[trial]
    return TransferUnit(
        trial=trial,
        task=group.held_out,
        layout_seed=layout,
        episode_seed=episode,
        harness=Path(HARNESS_DIR),
        key=b"",
        ledger_task=fresh_id(group, trial),
        steps=AGENT_STEPS,
        wall_time_s=AGENT_WALL_S,
        out_dir=out_dir,
    )


def harness_dir() -> Path:
    """The harness named by ``RLE_F02_HARNESS``.

    Raises:
        RleError: ``f02.no_harness`` when it is unset.
    """
    given = os.environ.get(HARNESS_ENV)
    if not given:
        raise RleError(
            f"a fresh agent's workspace holds the submitted harness: set {HARNESS_ENV} to its agent_harness/ "
            "directory",
            code="f02.no_harness",
        )
    return Path(given)


def make_dev_env(workspace: Path, group: Group, trial: int, harness: Path | None = None):
    """Copy the harness (``harness``, default ``RLE_F02_HARNESS``), write the held-out task's
    instruction; return the kitchen's metered env."""
    workspace = Path(workspace)
    try:
        copy_harness(harness or harness_dir(), workspace / HARNESS_DIR)
    except HarnessError as exc:
        raise RleError(str(exc), code="f02.harness_unusable") from None
    env = _env(_unit(group, trial, current_secret()), images=True)
    (workspace / "instruction.md").write_text(
        FRESH_INSTRUCTION.read_text().format(
            instruction=env.scene.episode.instruction, steps=AGENT_STEPS, minutes=AGENT_WALL_S / 60
        )
    )
    return env


def verify(root: Path, ctx: VerifyContext, group: Group, trial: int) -> VerifierReport:
    """Gate the session's ledger and score its replay (module docstring)."""
    task_id = fresh_id(group, trial)
    findings = Findings()
    path = Path(root) / "ledger.jsonl"
    gate = check_ledger(path, ledger_key(ctx.secret, task_id), task_id, LIMITS, ctx.attempt)

    def zero(code: str, message: str) -> VerifierReport:
        findings.add_error(code, message, "ledger.jsonl")
        return rubric(task_id).report(
            {"s_trial": Outcome({"agent": 0.0}, message)},
            valid=False,
            errors=findings.errors,
            native_metrics={"held_out": group.held_out, "trial": trial},
        )

    if not gate.ok:
        return zero(gate.code, gate.message)
    unit = _unit(group, trial, ctx.secret.for_attempt(gate.attempt), ctx.out_dir)
    try:
        names, b, m, success, recorded, _ = _stages(unit, path)
    except ReplayError as exc:
        return zero(exc.code, exc.message)
    score = stage_score(b, m, len(names), success, recorded)
    if not recorded:
        findings.add_error(
            "f02.no_stage_records", "the session holds no reset: nothing to score", "ledger.jsonl"
        )
    msg = f"b={b} m={m} n={len(names)}" + (", success" if success else "") + f", {gate.steps} steps"
    return rubric(task_id).report(
        {"s_trial": Outcome({"agent": score}, msg)},
        valid=True,
        errors=findings.errors,
        native_metrics={
            "held_out": group.held_out,
            "trial": trial,
            "stages": list(names),
            "b": b,
            "m": m,
            "n": len(names),
            "success": success,
            "steps": gate.steps,
            "attempt": {"id": gate.attempt, "bound": gate.attempt_bound},
        },
    )


def stage_task(task_id: str, harness: Path | None = None) -> TaskSpec | None:
    """The TaskSpec of fresh agent ``task_id`` (None for any other id); ``harness`` (default
    ``RLE_F02_HARNESS``) is what an export puts in its images."""
    found = _group(task_id)
    if found is None:
        return None
    group, trial = found
    source = (lambda: Path(harness)) if harness is not None else harness_dir
    return TaskSpec(
        id=task_id,
        family=2,
        title=f"RoboCasa harness transfer, group {group.number}: fresh agent {trial}",
        instruction=INSTRUCTION,
        budget=Budget(wall_time_s=AGENT_WALL_S, cpus=2, gpus=0, steps=AGENT_STEPS, verifier_timeout_s=1800.0),
        contract=ArtifactContract(
            required=("ledger.jsonl",),
            description="nothing to write: the verifier scores the session the metered server recorded",
        ),
        make_dev_env=functools.partial(make_dev_env, group=group, trial=trial, harness=harness),
        verify=functools.partial(verify, group=group, trial=trial),
        harbor_data=(ImageData(name=HARNESS_DIR, source=source, env=HARNESS_ENV, built="MANUAL.md"),),
        quick_reduces=False,
    )


def group_report(group: Group, rewards: list[float | None], trials: list[str]) -> VerifierReport:
    """The group's report from its fresh agents' rewards (a failed trial, run without a reward, counts
    0), in the group rubric's form, so that ``rle index`` takes it like the verifier's own. Fewer than
    ``TRIALS`` trials make it partial, scored over the trials that ran (as the verifier's quick mode)."""
    scores = [float(r) if r is not None else 0.0 for r in rewards][:TRIALS]
    total = sum(scores) / max(len(scores), 1)
    findings = Findings()
    for name, reward in zip(trials, rewards, strict=False):
        if reward is None:
            findings.add_error("f02.trial_failed", f"fresh trial {name}: no reward (counted 0)", HARNESS_DIR)
    msg = f"mean s_trial {total:.3f} over {len(scores)} fresh agents run as Harbor trials (" + ", ".join(
        f"{s:.2f}" for s in scores
    )
    msg += ")" if len(scores) == TRIALS else f"; partial: {TRIALS - len(scores)} of the {TRIALS} not run)"
    return group_rubric(group.task_id).report(
        {"transfer": Outcome({"agents": total}, msg, {"s_trial": scores})},
        valid=True,
        errors=findings.errors,
        native_metrics={
            "held_out": group.held_out,
            "successes": sum(s == 1.0 for s in scores),
            "fresh_trials": [{"trial": t, "reward": r} for t, r in zip(trials, rewards, strict=False)],
            "partial": len(scores) < TRIALS,
        },
    )
