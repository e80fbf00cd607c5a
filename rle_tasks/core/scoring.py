"""Declarative scoring: a task's rubric is declared once and the report is built from it.

A ``Rubric`` lists its checkpoints (id, weight, what is measured, the curve from measurement to score,
how variants combine, when a checkpoint counts as passed), the caps and the deductions. A verifier
measures and returns one ``Outcome`` per checkpoint (a score per variant, a message, the measured
values); ``Rubric.report`` combines them, applies deductions and caps, and returns the frozen
``VerifierReport``. The instruction's credit table and the family README's table are both
``Rubric.markdown_table()``, so the three cannot disagree.

Aggregation:
* ``"weighted"``: checkpoint score = combination (min or mean) of its variant scores; task score =
  sum of weight x checkpoint score;
* ``"variant_mean"``: each variant's score is its weighted checkpoint sum minus its deduction
  (floor 0); the task score is the mean over variants (written to ``native_metrics.variant_score``);
  a checkpoint's score is still the combination of its variant scores (for the credit column).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from rle_design.errors import RleError
from rle_tasks.core.report import Checkpoint, ErrorEntry, VerifierReport

Combine = Literal["min", "mean"]
Aggregate = Literal["weighted", "variant_mean"]


class RubricError(RleError):
    """A rubric declared or used inconsistently (our bug, never a participant fault)."""

    code = "scoring.rubric"


@dataclass(frozen=True)
class Linear:
    """Linear curve: 1 at or better than ``pass_value``, 0 at or worse than ``fail_value``.

    Either direction works (``pass_value < fail_value`` when smaller is better). Non-finite
    measurements score 0.
    """

    pass_value: float
    fail_value: float

    def __post_init__(self) -> None:
        if self.pass_value == self.fail_value:
            raise RubricError(f"linear curve needs pass != fail, got {self.pass_value}")

    def __call__(self, value: float) -> float:
        value = float(value)
        if not math.isfinite(value):
            return 0.0
        s = (self.fail_value - value) / (self.fail_value - self.pass_value)
        return float(np.clip(s, 0.0, 1.0))

    def threshold(self) -> dict[str, Any]:
        return {"pass": self.pass_value, "fail": self.fail_value, "curve": "linear"}

    def describe(self) -> str:
        return f"{self.pass_value:g} scores 1, {self.fail_value:g} scores 0, linear between"


@dataclass(frozen=True)
class Fraction:
    """The measurement is already a score in [0, 1] (a fraction of trials, poses or checks passed)."""

    what: str = "fraction passed"

    def __call__(self, value: float) -> float:
        value = float(value)
        return float(np.clip(value, 0.0, 1.0)) if math.isfinite(value) else 0.0

    def threshold(self) -> dict[str, Any]:
        return {}

    def describe(self) -> str:
        return self.what


Curve = Linear | Fraction


@dataclass(frozen=True)
class PassRule:
    """When a checkpoint counts as passed.

    Attributes:
        at: Score a variant (``over="each"``) or the combined score (``"combined"``) must reach.
        over: ``"combined"`` or ``"each"`` variant.
        strict: Require a score strictly above ``at`` instead of at least ``at``.
    """

    at: float = 1.0
    over: Literal["combined", "each"] = "combined"
    strict: bool = False

    def passed(self, score: float, per_variant: Mapping[str, float]) -> bool:
        values = [score] if self.over == "combined" else list(per_variant.values())
        if not values:
            return False
        return all((v > self.at) if self.strict else (v >= self.at) for v in values)


@dataclass(frozen=True)
class CheckpointSpec:
    """One declared checkpoint.

    Attributes:
        id: Stable id (report key).
        weight: Share of the task score [1].
        metric: What is measured, with units (the report's default message and the table's text).
        curve: From measurement to score.
        group: Rubric group of the task card, or "".
        combine: How variant scores combine into the checkpoint score.
        pass_rule: When the checkpoint counts as passed.
        threshold: Threshold shown in the report; None derives it from the curve.
    """

    id: str
    weight: float
    metric: str
    curve: Curve = field(default_factory=Fraction)
    group: str = ""
    combine: Combine = "min"
    pass_rule: PassRule = field(default_factory=PassRule)
    threshold: Mapping[str, Any] | None = None

    def score(self, value: float) -> float:
        """Score of one measurement."""
        return self.curve(value)

    def mean_score(self, values: Iterable[float]) -> float:
        """Mean of the per-sample scores (a sample per pose, trial, ...); 0 when there are none."""
        values = list(np.ravel(list(values)))
        if not values:
            return 0.0
        return float(np.mean([self.curve(v) for v in values]))

    def reported_threshold(self) -> dict[str, Any]:
        return dict(self.threshold) if self.threshold is not None else self.curve.threshold()


@dataclass(frozen=True)
class Cap:
    """A ceiling on the task score, applied when the verifier reports its condition.

    Attributes:
        id: Stable id the verifier names when the condition holds.
        value: Maximum score [1].
        reason: The condition, in words (instruction, README, report).
    """

    id: str
    value: float
    reason: str


@dataclass(frozen=True)
class Deduction:
    """Points removed from a variant's score for a validity finding.

    Attributes:
        code: Error code that triggers it.
        amount: Points removed [1].
        reason: The finding, in words.
    """

    code: str
    amount: float
    reason: str


@dataclass(frozen=True)
class Outcome:
    """What a verifier measured for one checkpoint.

    Attributes:
        per_variant: Score per variant in [0, 1] (arms, robots, scenes ...).
        message: Report message; None uses the checkpoint's metric.
        measured: Measured values, JSON-able.
    """

    per_variant: Mapping[str, float]
    message: str | None = None
    measured: Mapping[str, Any] = field(default_factory=dict)


def _combine(how: Combine, values: Sequence[float]) -> float:
    if not values:
        return 0.0
    return float(min(values)) if how == "min" else float(np.mean(values))


@dataclass(frozen=True)
class Rubric:
    """A task's checkpoints, caps and deductions.

    Attributes:
        task_id: Task the rubric scores.
        family: Two-digit family number.
        workflow: Workflow of the task.
        variants: Variant names in report order.
        checkpoints: Declared checkpoints; weights sum to 1.
        aggregate: ``"weighted"`` or ``"variant_mean"`` (see module docstring).
        caps: Declared caps.
        deductions: Declared deductions (per variant, distinct codes add up).
        max_deduction: Largest deduction of one variant [1].
    """

    task_id: str
    family: str
    workflow: str
    variants: tuple[str, ...]
    checkpoints: tuple[CheckpointSpec, ...]
    aggregate: Aggregate = "weighted"
    caps: tuple[Cap, ...] = ()
    deductions: tuple[Deduction, ...] = ()
    max_deduction: float = 0.0

    def __post_init__(self) -> None:
        ids = [c.id for c in self.checkpoints]
        if len(set(ids)) != len(ids):
            raise RubricError(f"{self.task_id}: duplicate checkpoint ids {ids}")
        total = sum(c.weight for c in self.checkpoints)
        if abs(total - 1.0) > 1e-9:
            raise RubricError(f"{self.task_id}: checkpoint weights sum to {total}, not 1")

    def spec(self, cid: str) -> CheckpointSpec:
        for c in self.checkpoints:
            if c.id == cid:
                return c
        raise RubricError(
            f"checkpoint '{cid}' is not declared for {self.task_id}. "
            f"Declared checkpoints: {', '.join(c.id for c in self.checkpoints)}"
        )

    def cap(self, cid: str) -> Cap:
        for c in self.caps:
            if c.id == cid:
                return c
        raise RubricError(
            f"cap '{cid}' is not declared for {self.task_id}; declared: {[c.id for c in self.caps]}"
        )

    def deduction(self, findings: Iterable[str | tuple[str, float]]) -> float:
        """Deduction of one variant: the distinct codes' amounts, summed and capped [1].

        Args:
            findings: Codes, or ``(code, fraction)`` pairs for a deduction that grows with the size of
                the shortfall (``fraction`` in [0, 1] of the declared amount; a code seen twice counts
                once, at its largest fraction).
        """
        amounts = {d.code: d.amount for d in self.deductions}
        worst: dict[str, float] = {}
        for f in findings:
            code, frac = (f, 1.0) if isinstance(f, str) else (f[0], min(1.0, max(0.0, float(f[1]))))
            worst[code] = max(worst.get(code, 0.0), frac)
        return min(self.max_deduction, sum(amounts.get(c, 0.0) * frac for c, frac in worst.items()))

    def report(
        self,
        outcomes: Mapping[str, Outcome],
        *,
        valid: bool,
        errors: Sequence[ErrorEntry] = (),
        caps: Iterable[str] = (),
        deductions: Mapping[str, float] | None = None,
        native_metrics: Mapping[str, Any] | None = None,
    ) -> VerifierReport:
        """The report of one verification.

        Args:
            outcomes: One outcome per declared checkpoint (a missing one scores 0 for every variant).
            valid: Whether the artifact met the contract.
            errors: Participant faults and findings.
            caps: Ids of the declared caps whose condition holds.
            deductions: Deduction per variant (``variant_mean`` only) [1].
            native_metrics: Task-native measurements.
        """
        unknown = set(outcomes) - {c.id for c in self.checkpoints}
        if unknown:
            raise RubricError(f"{self.task_id}: outcomes for undeclared checkpoints {sorted(unknown)}")
        checkpoints = []
        for spec in self.checkpoints:
            out = outcomes.get(spec.id, Outcome({v: 0.0 for v in self.variants}, "not measured"))
            per = {v: float(out.per_variant.get(v, 0.0)) for v in self.variants}
            score = _combine(spec.combine, list(per.values()))
            checkpoints.append(
                Checkpoint(
                    id=spec.id,
                    weight=spec.weight,
                    score=score,
                    passed=spec.pass_rule.passed(score, per),
                    message=spec.metric if out.message is None else out.message,
                    measured=dict(out.measured),
                    threshold=spec.reported_threshold(),
                    per_variant=per,
                )
            )
        native = dict(native_metrics or {})
        if self.aggregate == "weighted":
            score = sum(c.credit for c in checkpoints)
        else:
            ded = deductions or {}
            finals = {}
            for v in self.variants:
                total = sum(c.weight * c.per_variant[v] for c in checkpoints)
                finals[v] = max(0.0, total - float(ded.get(v, 0.0)))
            score = float(np.mean(list(finals.values())))
            native["variant_score"] = finals
        applied = [self.cap(cid) for cid in dict.fromkeys(caps)]
        cap = min((c.value for c in applied), default=None)
        if cap is not None:
            score = min(score, cap)
        return VerifierReport(
            task_id=self.task_id,
            family=self.family,
            workflow=self.workflow,
            score=score,
            valid=valid,
            cap=cap,
            checkpoints=tuple(checkpoints),
            native_metrics=native,
            errors=tuple(errors),
        )

    def markdown_table(self) -> str:
        """Checkpoint table (instruction and README), then caps and deductions."""
        groups = any(c.group for c in self.checkpoints)
        head = "| checkpoint |" + (" group |" if groups else "") + " weight | what is measured | scoring |"
        rows = [head, "|" + "---|" * (5 if groups else 4)]
        for c in self.checkpoints:
            how = c.curve.describe()
            if len(self.variants) > 1:
                how += f"; {'minimum' if c.combine == 'min' else 'mean'} over {', '.join(self.variants)}"
            group = f" {c.group} |" if groups else ""
            rows.append(f"| `{c.id}` |{group} {c.weight:.2f} | {c.metric} | {how} |")
        for cap in self.caps:
            rows.append("")
            rows.append(f"Cap `{cap.id}`: the score is at most {cap.value:g} when {cap.reason}.")
        if self.deductions:
            rows.append("")
            items = ", ".join(f"{d.reason} (`{d.code}`) -{d.amount:g}" for d in self.deductions)
            rows.append(f"Deductions per variant (at most {self.max_deduction:g}): {items}.")
        return "\n".join(rows)
