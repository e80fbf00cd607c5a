"""The ledger gate every verifier uses: authenticity, then every limit of the card re-checked on the records.

A sealed, authentic ledger (``verify_ledger``) proves only that the key's holder wrote it. The live
server enforces the card's limits, but a verifier must not depend on the server alone (a leaked or
mishandled key, a server bug, a session served with other settings), so ``check_ledger`` recounts
everything from the records themselves and compares it with ``Limits``:

============================ ===================================================================
code                         breach
============================ ===================================================================
``ledger.old_format``        the ledger predates ``records.FORMAT`` (no attempt, no wall stamps)
``ledger.wrong_attempt``     the open record names another attempt than the one being verified
``ledger.wrong_limits``      the server was opened with other limits than the card's (budget,
                             wall time, evaluation phase)
``ledger.over_budget``       more charged development steps than the budget
``ledger.over_time``         a step charged after the session's (or the evaluation phase's) wall
                             time, or wall stamps that run backwards
``ledger.too_many_trials``   more evaluation trials than the card's
``ledger.trial_too_long``    a trial with more actions than the card allows
``ledger.too_many_resets``   more development resets than the card allows
``ledger.seal_mismatch``     the seal's own account (development steps, per-trial actions, elapsed
                             time) disagrees with the records
============================ ===================================================================

Any breach makes the ledger unverifiable: the card's consequence is a zero ("a missing, unsealed, or
unverifiable ledger scores zero"). ``GateResult`` carries what was counted (development steps, resets,
per-trial actions) so that a verifier never counts again.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rle_design.ledger.records import CHARGED, FORMAT, cost
from rle_design.ledger.verify import LedgerVerdict, verify_ledger

__all__ = ["GATE_CODES", "GateResult", "Limits", "TrialCount", "check_ledger"]

WALL_TOLERANCE_S = 0.002
"""Slack on wall-time comparisons [s]: stamps are floored to 1 ms, and a phase's window is the
difference of two stamps (at most 1 ms too short each way)."""

GATE_CODES: dict[str, str] = {
    "ledger.old_format": "the ledger predates the current format (no attempt or wall stamps)",
    "ledger.wrong_attempt": "the ledger belongs to another attempt",
    "ledger.wrong_limits": "the session was served with other limits than the card's",
    "ledger.over_budget": "more charged development steps than the budget",
    "ledger.over_time": "a step was charged after the wall-time limit",
    "ledger.too_many_trials": "more evaluation trials than the card's",
    "ledger.trial_too_long": "an evaluation trial took more actions than allowed",
    "ledger.too_many_resets": "more development resets than allowed",
    "ledger.seal_mismatch": "the seal's account disagrees with the records",
}


@dataclass(frozen=True)
class Limits:
    """The card's limits of one task's session.

    Attributes:
        budget: Charged development steps allowed (None: unmetered).
        wall_time_s: Wall time of the session [s]; the server must have been opened with a limit no
            larger, and no step may be charged later (None: no limit required).
        trials: Evaluation trials (None: the session has no evaluation phase).
        actions_per_trial: Actions one evaluation trial may take.
        evaluation_wall_time_s: Wall time of the evaluation phase from its first reset [s].
        resets: Development resets allowed (None: any).
    """

    budget: int | None
    wall_time_s: float | None = None
    trials: int | None = None
    actions_per_trial: int | None = None
    evaluation_wall_time_s: float | None = None
    resets: int | None = None


@dataclass(frozen=True)
class TrialCount:
    """What the records say of one evaluation trial: its scene, its actions, the seal's account."""

    trial: int
    scene: str
    actions: int
    recorded_success: bool | None


@dataclass(frozen=True)
class GateResult:
    """Result of ``check_ledger``.

    Attributes:
        ok: Authentic and within every limit.
        code: ``"ledger.valid"`` or the first failure (``VERDICT_CODES`` or ``GATE_CODES``).
        message: Reason naming the record.
        verdict: The authenticity verdict.
        attempt: The attempt the open record names ("" when unbound).
        attempt_bound: The caller named the attempt it verifies (else the ledger's own was taken).
        development_steps: Charged steps before the first evaluation reset.
        resets: Development resets.
        actions: Executed actions, all phases.
        trials: Per-trial counts of the evaluation phase.
        last_wall_s: Wall stamp of the last charged record [s].
    """

    ok: bool
    code: str
    message: str
    verdict: LedgerVerdict | None = None
    attempt: str = ""
    attempt_bound: bool = False
    development_steps: int = 0
    resets: int = 0
    actions: int = 0
    trials: tuple[TrialCount, ...] = ()
    last_wall_s: float = 0.0

    @property
    def opened(self) -> dict:
        return self.verdict.opened if self.verdict is not None else {}

    @property
    def privileged(self) -> bool:
        """The session served privileged observations (an operator's oracle run, never an agent's)."""
        return self.opened.get("privileged") is True

    @property
    def sealed(self) -> dict:
        return self.verdict.sealed if self.verdict is not None else {}

    @property
    def steps(self) -> int:
        return self.verdict.steps if self.verdict is not None else 0


def _fail(code: str, message: str, verdict: LedgerVerdict | None = None, **kw: Any) -> GateResult:
    return GateResult(False, code, message, verdict, **kw)


def _num(x: Any) -> float | None:
    return float(x) if isinstance(x, (int, float)) and not isinstance(x, bool) else None


def _limits_problem(opened: dict, limits: Limits) -> str | None:
    if opened.get("budget") != limits.budget:
        return f"the session's development budget was {opened.get('budget')!r} steps, the card's is {limits.budget}"
    if limits.wall_time_s is not None:
        w = _num(opened.get("wall_time_s"))
        if w is None or not 0 < w <= limits.wall_time_s:
            return (
                f"the session was limited to {opened.get('wall_time_s')!r} s of wall time, the card allows "
                f"{limits.wall_time_s:.0f} s"
            )
    if limits.trials is not None:
        e = opened.get("evaluation") or {}
        want = {
            "trials": limits.trials,
            "actions_per_trial": limits.actions_per_trial,
            "wall_time_s": limits.evaluation_wall_time_s,
        }
        if not isinstance(e, dict) or any(e.get(k) != v for k, v in want.items()):
            return f"the session's evaluation phase was {e!r}, the card's is {want}"
    return None


def check_ledger(
    path: str | Path, key: bytes, task_id: str, limits: Limits, attempt: str | None = None
) -> GateResult:
    """Verify ``path`` under ``key`` and re-check every limit of ``limits`` on its records.

    Args:
        path: The submitted ledger (a regular file; a symlink is refused).
        key: The verifier's ledger key for ``task_id``.
        task_id: The task the ledger must belong to.
        limits: The card's limits.
        attempt: The attempt being verified (the operator's id); None takes the ledger's own and
            reports it as unbound.

    Returns:
        A result; never raises on bad input.
    """
    path = Path(path)
    if path.is_symlink() or (path.exists() and not path.is_file()):
        return _fail("ledger.missing", f"{path.name} is not a regular file")
    verdict = verify_ledger(path, key, task_id)
    if not verdict.valid:
        return _fail(verdict.code, verdict.message, verdict)
    opened = verdict.opened
    if opened.get("format") != FORMAT or not isinstance(opened.get("attempt"), str):
        return _fail(
            "ledger.old_format",
            f"{path.name} is of ledger format {opened.get('format')!r}, this verifier reads format {FORMAT}; "
            "record the session again with the current `rle dev`",
            verdict,
        )
    own = opened["attempt"]
    if attempt is not None and own != attempt:
        return _fail(
            "ledger.wrong_attempt",
            f"{path.name} was recorded in attempt {own!r}, this verification is of attempt {attempt!r}",
            verdict,
            attempt=own,
        )
    ctx = {"attempt": own, "attempt_bound": attempt is not None}
    problem = _limits_problem(opened, limits)
    if problem:
        return _fail("ledger.wrong_limits", f"{path.name}: {problem}", verdict, **ctx)
    try:
        recs = [json.loads(line) for line in path.read_bytes().splitlines()]
    except (OSError, ValueError):  # verify_ledger read it a moment ago
        return _fail("ledger.missing", f"{path.name} cannot be read again", verdict, **ctx)
    return _recount(path.name, recs, verdict, limits, ctx)


def _recount(name: str, recs: list[dict], verdict: LedgerVerdict, limits: Limits, ctx: dict) -> GateResult:
    limit = _num(verdict.opened.get("wall_time_s"))
    dev_steps = resets = actions = 0
    trials: list[list[Any]] = []  # [scene, actions, first wall]
    wall = 0.0
    for rec in recs[1:-1]:
        kind, p = rec["kind"], rec["payload"]
        if kind not in CHARGED:
            continue
        w = _num(p.get("wall"))
        line = f"{name}: line {rec['seq'] + 1}"
        if w is None or w < wall:
            return _fail(
                "ledger.over_time", f"{line} has wall stamp {p.get('wall')!r} after {wall}", verdict, **ctx
            )
        wall = w
        if limit is not None and w > limit + WALL_TOLERANCE_S:
            return _fail(
                "ledger.over_time", f"{line} was charged at {w:.3f} s, the session's limit is {limit:.0f} s", verdict, **ctx
            )  # fmt: skip
        n = cost(kind, p) or 0
        if kind == "reset" and p.get("phase") == "evaluation":
            if p.get("trial") != len(trials):
                return _fail("ledger.seal_mismatch", f"{line} starts trial {p.get('trial')!r}, expected {len(trials)}", verdict, **ctx)  # fmt: skip
            trials.append([str(p.get("scene", "")), 0, w])
            if limits.trials is None or len(trials) > limits.trials:
                return _fail(
                    "ledger.too_many_trials",
                    f"{line} starts evaluation trial {len(trials)}, the card allows {limits.trials or 0}",
                    verdict, **ctx,
                )  # fmt: skip
        elif trials:
            if kind == "reset":
                return _fail("ledger.seal_mismatch", f"{line} is a development reset after the evaluation began", verdict, **ctx)  # fmt: skip
            trials[-1][1] += n
            if limits.actions_per_trial is not None and trials[-1][1] > limits.actions_per_trial:
                return _fail(
                    "ledger.trial_too_long",
                    f"{line}: trial {len(trials) - 1} has {trials[-1][1]} actions, the card allows {limits.actions_per_trial}",
                    verdict, **ctx,
                )  # fmt: skip
        else:
            dev_steps += n
            resets += kind == "reset"
            if limits.budget is not None and dev_steps > limits.budget:
                return _fail(
                    "ledger.over_budget",
                    f"{line} charges development step {dev_steps}, the budget is {limits.budget}",
                    verdict, **ctx,
                )  # fmt: skip
            if limits.resets is not None and resets > limits.resets:
                return _fail(
                    "ledger.too_many_resets", f"{line} is development reset {resets}, the card allows {limits.resets}",
                    verdict, **ctx,
                )  # fmt: skip
        if kind == "steps":
            actions += n
        if trials and limits.evaluation_wall_time_s is not None:
            spent = w - trials[0][2]
            if spent > limits.evaluation_wall_time_s + WALL_TOLERANCE_S:
                return _fail(
                    "ledger.over_time",
                    f"{line} was charged {spent:.3f} s into the evaluation phase, the card allows "
                    f"{limits.evaluation_wall_time_s:.0f} s",
                    verdict, **ctx,
                )  # fmt: skip
    sealed = verdict.sealed
    problem = _seal_problem(sealed, dev_steps, trials, wall, limit)
    if problem:
        return _fail("ledger.seal_mismatch", f"{name}: {problem}", verdict, **ctx)
    recorded = sealed.get("trials") if isinstance(sealed.get("trials"), list) else []
    counts = tuple(
        TrialCount(
            k,
            scene,
            n,
            recorded[k]["success"]
            if k < len(recorded) and isinstance(recorded[k].get("success"), bool)
            else None,
        )
        for k, (scene, n, _) in enumerate(trials)
    )
    return GateResult(
        True, "ledger.valid", verdict.message, verdict, development_steps=dev_steps, resets=resets,
        actions=actions, trials=counts, last_wall_s=wall, **ctx,
    )  # fmt: skip


def _seal_problem(sealed: dict, dev_steps: int, trials: list, wall: float, limit: float | None) -> str | None:
    if "development_steps" in sealed and sealed["development_steps"] != dev_steps:
        return f"the seal counts {sealed['development_steps']!r} development steps, the records {dev_steps}"
    if "trials" in sealed:
        rec = sealed["trials"]
        if not isinstance(rec, list) or len(rec) != len(trials):
            n = len(rec) if isinstance(rec, list) else rec
            return f"the seal lists {n!r} trials, the records {len(trials)}"
        for k, (t, (scene, n, _)) in enumerate(zip(rec, trials)):
            if not isinstance(t, dict) or t.get("actions") != n or t.get("scene") != scene:
                got = t.get("actions") if isinstance(t, dict) else t
                return f"the seal gives trial {k} {got!r} actions, the records {n}"
    if limit is not None:
        elapsed = _num(sealed.get("elapsed_s"))
        if elapsed is None or elapsed + WALL_TOLERANCE_S < wall:
            return f"the seal says the session took {sealed.get('elapsed_s')!r} s, its last step was charged at {wall:.3f} s"
    return None
