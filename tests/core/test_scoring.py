"""Declarative scoring and the frozen report: aggregation, caps, deductions, pass rules, JSON."""

import dataclasses
import json

import pytest

from rle_tasks.core.report import Checkpoint, ErrorEntry, VerifierReport
from rle_tasks.core.scoring import (
    Cap,
    CheckpointSpec,
    Deduction,
    Fraction,
    Linear,
    Outcome,
    PassRule,
    Rubric,
    RubricError,
)


def _rubric(**kw):
    base = dict(
        task_id="00-x",
        family="00",
        workflow="mechanical_design",
        variants=("a", "b"),
        checkpoints=(
            CheckpointSpec("fit", 0.6, "fit error [m]", Linear(0.01, 0.11)),
            CheckpointSpec("held", 0.4, "trials held", Fraction(), combine="mean"),
        ),
        caps=(Cap("broken", 0.15, "the part is broken"),),
        deductions=(Deduction("heavy", 0.1, "too heavy"), Deduction("thin", 0.05, "too thin")),
        max_deduction=0.12,
    )
    base.update(kw)
    return Rubric(**base)


def test_linear_curve_both_directions_and_non_finite():
    smaller = Linear(0.01, 0.11)
    assert smaller(0.06) == pytest.approx(0.5) and smaller(0.0) == 1.0 and smaller(0.2) == 0.0
    larger = Linear(10.0, 0.0)
    assert larger(2.5) == pytest.approx(0.25) and larger(float("nan")) == 0.0
    with pytest.raises(RubricError, match="pass != fail"):
        Linear(1.0, 1.0)


def test_weighted_aggregation_combines_variants_and_applies_caps():
    r = _rubric()
    fit = r.spec("fit")
    outcomes = {
        "fit": Outcome({"a": fit.score(0.06), "b": fit.score(0.01)}),  # 0.5, 1.0 -> min 0.5
        "held": Outcome({"a": 1.0, "b": 0.5}, "1 failed"),  # mean 0.75
    }
    rep = r.report(outcomes, valid=True)
    # 0.6 * 0.5 + 0.4 * 0.75 = 0.6
    assert rep.score == pytest.approx(0.6) and rep.cap is None
    assert [c.score for c in rep.checkpoints] == [pytest.approx(0.5), pytest.approx(0.75)]
    assert rep.checkpoint("fit").message == "fit error [m]" and rep.checkpoint("held").message == "1 failed"
    assert rep.checkpoint("fit").threshold == {"pass": 0.01, "fail": 0.11, "curve": "linear"}
    capped = r.report(outcomes, valid=False, caps=["broken"])
    assert capped.score == 0.15 and capped.cap == 0.15 and not capped.valid


def test_variant_mean_aggregation_with_deductions():
    r = _rubric(aggregate="variant_mean")
    outcomes = {"fit": Outcome({"a": 1.0, "b": 0.5}), "held": Outcome({"a": 1.0, "b": 0.0})}
    ded = {"a": r.deduction(["heavy", "thin", "heavy"]), "b": r.deduction([])}
    assert ded == {"a": 0.12, "b": 0.0}  # 0.10 + 0.05 capped at 0.12; repeated codes count once
    rep = r.report(outcomes, valid=True, deductions=ded)
    # a: 0.6 + 0.4 - 0.12 = 0.88; b: 0.3 + 0 = 0.3; mean 0.59
    assert rep.native_metrics["variant_score"] == {"a": pytest.approx(0.88), "b": pytest.approx(0.3)}
    assert rep.score == pytest.approx(0.59)


def test_a_deduction_grows_with_the_shortfall():
    r = _rubric(aggregate="variant_mean")
    # heavy 0.10 x 0.3 = 0.03; the same code twice counts once at its largest fraction (0.6 -> 0.06)
    assert r.deduction([("heavy", 0.3)]) == pytest.approx(0.03)
    assert r.deduction([("heavy", 0.3), ("heavy", 0.6)]) == pytest.approx(0.06)
    # fractions are clamped to [0, 1]; a plain code is a full deduction: 0.10 + 0.05 x 0.5 = 0.125 -> cap 0.12
    assert r.deduction([("heavy", 7.0), ("thin", 0.5)]) == pytest.approx(0.12)
    assert r.deduction([("heavy", -1.0)]) == 0.0
    assert r.deduction(["thin", ("heavy", 0.2)]) == pytest.approx(0.05 + 0.02)


def test_pass_rules_and_missing_outcomes():
    r = _rubric(
        checkpoints=(
            CheckpointSpec("each", 0.5, "m", pass_rule=PassRule(0.999, over="each"), combine="mean"),
            CheckpointSpec("positive", 0.5, "m", pass_rule=PassRule(0.0, strict=True)),
        )
    )
    rep = r.report({"each": Outcome({"a": 1.0, "b": 0.99})}, valid=True)
    assert not rep.checkpoint("each").passed  # b is below 0.999
    assert rep.checkpoint("positive").score == 0.0 and not rep.checkpoint("positive").passed
    assert rep.checkpoint("positive").message == "not measured"
    ok = r.report(
        {"each": Outcome({"a": 1.0, "b": 1.0}), "positive": Outcome({"a": 0.1, "b": 0.2})}, valid=True
    )
    assert ok.checkpoint("each").passed and ok.checkpoint("positive").passed


def test_declaration_errors_name_what_is_wrong():
    with pytest.raises(RubricError, match="weights sum to 0.9, not 1"):
        _rubric(checkpoints=(CheckpointSpec("x", 0.9, "m"),))
    with pytest.raises(RubricError, match=r"duplicate checkpoint ids \['x', 'x'\]"):
        _rubric(checkpoints=(CheckpointSpec("x", 0.5, "m"), CheckpointSpec("x", 0.5, "m")))
    r = _rubric()
    with pytest.raises(
        RubricError, match="checkpoint 'nope' is not declared for 00-x. Declared checkpoints: fit, held"
    ):
        r.spec("nope")
    with pytest.raises(RubricError, match=r"outcomes for undeclared checkpoints \['nope'\]"):
        r.report({"nope": Outcome({"a": 1.0})}, valid=True)
    with pytest.raises(RubricError, match="cap 'x' is not declared"):
        r.report({}, valid=True, caps=["x"])


def test_markdown_table_lists_every_checkpoint_cap_and_deduction():
    table = _rubric().markdown_table().splitlines()
    assert table[0] == "| checkpoint | weight | what is measured | scoring |"
    assert (
        table[2]
        == "| `fit` | 0.60 | fit error [m] | 0.01 scores 1, 0.11 scores 0, linear between; minimum over a, b |"
    )
    assert "Cap `broken`: the score is at most 0.15 when the part is broken." in table
    assert table[-1].startswith("Deductions per variant (at most 0.12): too heavy (`heavy`) -0.1")


def test_report_is_frozen_and_its_json_follows_the_field_order():
    cp = Checkpoint("fit", 0.6, 1.7, True, per_variant={"a": 1.0})
    assert cp.score == 1.0 and cp.credit == pytest.approx(0.6)  # clamped to [0, 1]
    rep = VerifierReport("00-x", "00", "w", score=0.4, checkpoints=(cp,), errors=(ErrorEntry("c", "m"),))
    with pytest.raises(dataclasses.FrozenInstanceError):
        rep.score = 1.0
    d = rep.to_dict()
    assert list(d) == [f.name for f in dataclasses.fields(VerifierReport)]
    assert list(d["checkpoints"][0])[:5] == ["id", "weight", "score", "credit", "passed"]
    back = VerifierReport.from_dict(json.loads(rep.to_json()))
    assert back == rep
    assert VerifierReport("00-x", "00", "w", score=float("nan")).to_dict()["score"] == 0.0
