"""Verifier of 04-dance on artifacts that must fail, each for its reason, and on the open-loop and
zero-action baselines (quick mode: two hidden seeds, public development key)."""

import json
import os

import numpy as np
import pytest

from rle_tasks.core.runtime.secrets import load_secret
from rle_tasks.core.task import VerifyContext
from rle_tasks.f04_motion_tracking.solutions import baselines
from rle_tasks.f04_motion_tracking.verifier import verify

CTX = VerifyContext(secret=load_secret(None), quick=True)


def _verify(tmp_path, build):
    build(tmp_path)
    return verify(tmp_path, CTX, task_id="04-dance")


def _codes(report):
    return {e.code for e in report.errors}


def test_twelve_million_parameters_is_invalid(tmp_path):
    r = _verify(tmp_path, baselines.twelve_million)
    assert not r.valid and r.score == 0.0 and r.cap == 0.0
    assert "f04.params" in _codes(r) and "12,096,000 parameters" in r.errors[0].message


def test_nan_output_is_a_smoke_failure(tmp_path):
    r = _verify(tmp_path, baselines.nan_output)
    assert r.valid and r.cap == 0.1 and r.score <= 0.1
    assert {"f04.smoke", "onnx.nonfinite"} <= _codes(r)
    assert r.native_metrics["survival_pct"] == 0.0


def test_output_varying_between_identical_calls_is_a_smoke_failure(tmp_path):
    r = _verify(tmp_path, baselines.non_deterministic)
    assert r.cap == 0.1 and r.score <= 0.1
    assert any(e.code == "f04.smoke" and "different outputs" in e.message for e in r.errors)


@pytest.mark.parametrize(
    ("meta", "expect"),
    [
        ({"history": 0}, "history must be an integer from 1 to 16"),
        ({"history": 1, "action_scale": [0.3] * 28}, "action_scale must be 29 finite numbers"),
        ("[1, 2]", "must be a JSON object"),
    ],
)
def test_bad_meta_is_invalid(tmp_path, meta, expect):
    baselines.open_loop(tmp_path)
    good = json.loads((tmp_path / "policy_meta.json").read_text())
    text = meta if isinstance(meta, str) else json.dumps({**good, **meta})
    (tmp_path / "policy_meta.json").write_text(text)
    r = verify(tmp_path, CTX, task_id="04-dance")
    assert not r.valid and r.score == 0.0 and "f04.meta" in _codes(r)
    assert expect in r.errors[0].message


def test_policy_outside_the_submission_is_refused(tmp_path):
    outside = tmp_path / "outside"
    baselines.open_loop(outside)
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "policy_meta.json").write_text((outside / "policy_meta.json").read_text())
    os.symlink(outside / "policy.onnx", sub / "policy.onnx")
    r = verify(sub, CTX, task_id="04-dance")
    assert not r.valid and "onnx.path" in _codes(r)


@pytest.mark.physics
def test_open_loop_beats_zero_action_natively_and_both_fall_within_the_first_seconds(tmp_path):
    """Both fall in about a second: 0.7 T + 0.3 U < 0.05 (T <= U since a step after the fall counts 0),
    so s <= 0.7 T + 0.3 U - 0.05 F < 0 scores 0 for both; open-loop replay tracks longer and better."""
    ol = _verify(tmp_path / "ol", baselines.open_loop)
    zero = _verify(tmp_path / "zero", baselines.zero_action)
    again = _verify(tmp_path / "ol2", baselines.open_loop)
    assert ol.valid and zero.valid and ol.cap is None and zero.cap is None
    assert ol.score == zero.score == 0.0
    for r in (ol, zero):
        for seed in r.native_metrics["seeds"].values():
            assert seed["T"] <= seed["U"] and seed["fell"] and seed["s"] == 0.0
            assert 0.7 * seed["T"] + 0.3 * seed["U"] < 0.05
    assert ol.native_metrics["survival_pct"] > zero.native_metrics["survival_pct"]
    t = [np.mean([s["T"] for s in r.native_metrics["seeds"].values()]) for r in (ol, zero)]
    assert t[0] > t[1]
    assert ol.native_metrics == again.native_metrics  # deterministic: same artifact, seed, secret


def test_parameters_hidden_in_a_constant_node_count(tmp_path):
    """10.5 M zeros in a Constant node (not an initializer) still count: 10,500,000 + the open-loop
    graph's 160 x 29 + 29 = 10,504,669 > 10 M."""
    import onnx
    from onnx import helper, numpy_helper

    baselines.open_loop(tmp_path)
    model = onnx.load(tmp_path / "policy.onnx")
    big = numpy_helper.from_array(np.zeros(10_500_000, np.float32), "big")
    out = model.graph.output[0].name
    model.graph.node[-1].output[0] = "pre"
    model.graph.node.extend(
        [
            helper.make_node("Constant", [], ["big"], value=big),
            helper.make_node("ReduceSum", ["big"], ["zero"], keepdims=0),
            helper.make_node("Add", ["pre", "zero"], [out]),
        ]
    )
    (tmp_path / "policy.onnx").write_bytes(model.SerializeToString())
    r = verify(tmp_path, CTX, task_id="04-dance")
    assert not r.valid and "f04.params" in _codes(r) and "10,504,669 parameters" in r.errors[0].message
