"""Ledger cases of the limit gate, shared by the families whose artifact is a session ledger.

Each case is a ledger written with the audit secret's ledger key (the stand-in for a leaked key:
every MAC is right) that breaks one limit of the card, so that only the gate's recount
(``rle_design.ledger.check_ledger``) or the replay can refuse it, by name. A family declares its
session's open record and limits in a ``LimitCases`` and lists ``limit_cases(...)`` in its ``audit.py``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rle_design.ledger.testing import forge_ledger
from rle_tasks.audit.case import Case

__all__ = ["AUDIT_ATTEMPT", "LimitCases", "limit_cases"]

AUDIT_ATTEMPT = "audit-attempt-1"
"""The attempt the limit cases are verified as (``Case.attempt``)."""


@dataclass(frozen=True)
class LimitCases:
    """What a family's honest session looks like, to break one limit at a time.

    Attributes:
        task_id: The task verified.
        open_meta: ``() -> dict``: the open record of the task's session (limits, scene digests).
        action_size: Numbers per action.
        budget: Charged development steps (card).
        wall_time_s: The session's wall time (card) [s].
        dev_reset: Payload fields of a development reset (scene key ...).
        trials: Evaluation trials (None without an evaluation phase).
        actions_per_trial: Actions one trial may take.
        evaluation_wall_time_s: Wall time of the evaluation phase [s].
        trial_reset: ``(k) -> dict``: payload fields of evaluation trial k's reset.
        out_of_range: ``() -> (records, seal)`` of a session whose one action lies outside the
            action range with the real scene digests (None: not built for this family).
    """

    task_id: str
    open_meta: Callable[[], dict[str, Any]]
    action_size: int
    budget: int
    wall_time_s: float
    dev_reset: dict[str, Any]
    trials: int | None = None
    actions_per_trial: int | None = None
    evaluation_wall_time_s: float | None = None
    trial_reset: Callable[[int], dict[str, Any]] | None = None
    out_of_range: Callable[[], tuple[list, dict]] | None = None


def _hold(n: int, size: int) -> list[str]:
    return [np.zeros(size).tobytes().hex()] * n


def _key(task_id: str) -> bytes:
    from rle_tasks.audit.case import AUDIT_SECRET
    from rle_tasks.core.runtime.devenv import ledger_key

    return ledger_key(AUDIT_SECRET, task_id)


def _build(spec: LimitCases, make: Callable[[], tuple[list, dict]], **meta: Any) -> Callable[[Path], Path]:
    def build(d: Path) -> Path:
        records, seal = make()
        opened = {**spec.open_meta(), "attempt": AUDIT_ATTEMPT, **meta}
        forge_ledger(d / "ledger.jsonl", _key(spec.task_id), spec.task_id, opened, records, seal)
        return d

    return build


def limit_cases(spec: LimitCases, family: str) -> list[Case]:
    """One case per limit of ``spec``'s card (names ``ledger/<family>_<limit>``)."""
    n = spec.action_size
    reset = [("reset", {**spec.dev_reset, "wall": 1.0})]
    trials = spec.trials is not None

    def dev_only(actions: int, wall: float = 1.0, elapsed: float | None = None) -> Callable:
        def make() -> tuple[list, dict]:
            recs = reset + [("steps", {"actions": _hold(actions, n), "wall": wall})]
            seal: dict[str, Any] = {"elapsed_s": elapsed if elapsed is not None else wall + 1.0}
            if trials:
                seal.update(development_steps=1 + actions, trials=[])
            return recs, seal

        return make

    def evaluation(
        lengths: list[int], last_wall: float = 2.0, seal_actions: list[int] | None = None
    ) -> Callable:
        def make() -> tuple[list, dict]:
            recs = list(reset)
            for k, a in enumerate(lengths):
                recs.append(("reset", {**spec.trial_reset(k), "wall": 2.0}))
                if a:
                    recs.append(("steps", {"actions": _hold(a, n), "wall": last_wall}))
            counts = seal_actions or lengths
            seal = {
                "development_steps": 1,
                "trials": [
                    {
                        "scene": spec.trial_reset(k)["scene"],
                        "actions": a,
                        "success": False,
                        "success_at": None,
                    }
                    for k, a in enumerate(counts)
                ],
                "elapsed_s": last_wall + 1.0,
            }
            return recs, seal

        return make

    def case(name: str, expect: str, build: Callable, attempt: str = AUDIT_ATTEMPT) -> Case:
        return Case(f"ledger/{family}_{name}", spec.task_id, expect, build, wall_cap_s=60.0, attempt=attempt)

    out = [
        case("over_budget", "ledger.over_budget", _build(spec, dev_only(spec.budget))),
        case("over_time", "ledger.over_time", _build(spec, dev_only(5, wall=spec.wall_time_s + 1.0))),
        case("seal_elapsed", "ledger.seal_mismatch", _build(spec, dev_only(5, wall=100.0, elapsed=10.0))),
        case("wrong_attempt", "ledger.wrong_attempt", _build(spec, dev_only(5)), attempt="audit-attempt-2"),
        case("old_format", "ledger.old_format", _build(spec, dev_only(5), format=1)),
        case("no_time_limit", "ledger.wrong_limits", _build(spec, dev_only(5), wall_time_s=None)),
        case("larger_budget", "ledger.wrong_limits", _build(spec, dev_only(5), budget=10 * spec.budget)),
    ]
    if trials:
        per, t = spec.actions_per_trial, spec.trials
        out += [
            case("trial_too_long", "ledger.trial_too_long", _build(spec, evaluation([per + 1]))),
            case("too_many_trials", "ledger.too_many_trials", _build(spec, evaluation([0] * (t + 1)))),
            case("seal_trial_count", "ledger.seal_mismatch", _build(spec, evaluation([3], seal_actions=[1]))),
            case(
                "evaluation_over_time",
                "ledger.over_time",
                _build(spec, evaluation([3], last_wall=2.0 + spec.evaluation_wall_time_s + 1.0)),
            ),
        ]
    if spec.out_of_range is not None:
        out.append(case("action_out_of_range", "ledger.action_out_of_range", _build(spec, spec.out_of_range)))
    return out
