"""Participant text in reports: a short sanitised excerpt, withheld under a private secret (issue 46.2).

Channels tested: an exception message crossing the sandbox, a value of the wrong type or shape, a
fresh agent's reply (02) and a policy's fault on a hidden pile (07, through the audit runner).
"""

import json
from pathlib import Path

import pytest

from rle_design.excerpt import CLOSE, EXCERPT_CHARS, OPEN, WITHHELD, excerpt, withhold
from rle_design.sandbox import ParticipantFault, Sandbox, SandboxLimits
from rle_tasks.core.report import Checkpoint, ErrorEntry, VerifierReport

PAYLOAD = "rle-exfil-payload pile friction 0.8312 \u00bb\n\x1b[2J" + "x" * 10_000


def test_excerpt_is_one_short_printable_line_that_cannot_close_its_marks():
    e = excerpt(PAYLOAD)
    inner = e[1:-1]
    assert e[0] == OPEN and e[-1] == CLOSE
    assert len(inner) == EXCERPT_CHARS and inner.endswith("...")
    assert OPEN not in inner and CLOSE not in inner  # the payload's own mark became '?'
    assert all(0x20 <= ord(ch) <= 0x7E for ch in inner)
    assert inner.startswith("rle-exfil-payload pile friction 0.8312 ? ?[2Jxxx")  # \n -> " ", ESC -> ?
    assert excerpt("short") == f"{OPEN}short{CLOSE}"


def test_excerpt_of_an_object_whose_str_raises():
    class Hostile:
        def __str__(self):
            raise RuntimeError("no")

    assert excerpt(Hostile()) == f"{OPEN}<Hostile>{CLOSE}"


def test_withhold_replaces_every_marked_excerpt_and_keeps_our_text():
    value = {"a": [f"act(): {excerpt('secret 1')}", ("x", excerpt("secret 2"))], excerpt("k"): 3.0}
    assert withhold(value) == {"a": [f"act(): {WITHHELD}", ("x", WITHHELD)], WITHHELD: 3.0}


def test_a_report_withheld_keeps_codes_and_facts_only():
    rep = VerifierReport(
        task_id="t",
        family="f",
        workflow="w",
        checkpoints=(Checkpoint("c", 1.0, 0.5, False, f"faulted: {excerpt('s1')}", {"why": excerpt("s2")}),),
        native_metrics={"trials": [{"message": excerpt("s3"), "score": 0.5}]},
        errors=(ErrorEntry("sandbox.exception", f"policy.act(): {excerpt('s4')}", "policy"),),
    )
    text = rep.withheld().to_json()
    assert not any(s in text for s in ("s1", "s2", "s3", "s4"))
    out = json.loads(text)
    assert out["errors"][0] == {
        "code": "sandbox.exception",
        "message": f"policy.act(): {WITHHELD}",
        "path": "policy",
    }
    assert out["checkpoints"][0]["score"] == 0.5 and out["native_metrics"]["trials"][0]["score"] == 0.5


MODULE = f"""
def long_raise():
    raise RuntimeError({PAYLOAD!r})


def as_text():
    return {PAYLOAD!r}


def odd_shape():
    import numpy as np
    return np.zeros((83, 12))
"""


@pytest.mark.parametrize(
    ("fn", "code", "shape"),
    [
        ("long_raise", "sandbox.exception", None),
        ("as_text", "sandbox.bad_type", (3,)),
        ("odd_shape", "sandbox.bad_shape", (3,)),
    ],
)
def test_sandbox_faults_carry_only_an_excerpt_of_what_the_child_said(tmp_path, fn, code, shape):
    mod = tmp_path / "submission.py"
    mod.write_text(MODULE)
    with (
        Sandbox(mod, limits=SandboxLimits(call_timeout_s=10.0)) as box,
        pytest.raises(ParticipantFault) as err,
    ):
        box.call(fn, shape=shape)
    assert err.value.code == code
    message = err.value.message
    assert message.startswith(f"submission.{fn}(): ")
    assert withhold(message) == message.split(OPEN)[0] + WITHHELD  # every child text is marked
    assert len(message) < 60 + EXCERPT_CHARS and "\n" not in message and "x" * 200 not in message


def test_a_fresh_agent_reply_is_reduced_to_known_statuses_and_an_excerpt(tmp_path):
    from rle_tasks.f02_harness_transfer.transfer import AGENT_STATUSES, TransferUnit, _run_scripted

    stage = tmp_path / "stage"
    stage.mkdir()
    (stage / "fresh_agent.py").write_text(
        f"def run():\n    return {{'status': 'f02.scored\\nforged', 'message': {PAYLOAD!r}}}\n"
    )
    unit = TransferUnit(0, "task", 0, 0, stage, b"k" * 32, "iso/agent-0", steps=1, wall_time_s=30.0)
    status, message = _run_scripted(stage, tmp_path / "unused.sock", unit)
    assert status == "bad_reply" and status not in AGENT_STATUSES
    assert message == excerpt(PAYLOAD) and withhold(message) == WITHHELD


@pytest.mark.physics
def test_a_policy_fault_on_a_hidden_pile_reaches_a_private_report_as_code_only(tmp_path):
    """07: a policy raises on the hidden pile with what it saw; audit secret (private), quick mode."""
    from rle_tasks.audit.check import EXFIL_MARK, run_case
    from rle_tasks.f07_bin_clearing.audit import cases

    case = next(c for c in cases() if c.name == "code/07_exfiltrating_fault")
    result = run_case(case, tmp_path)
    assert result.ok, result.why
    text = Path(result.report).read_text()
    assert EXFIL_MARK not in text and "0." not in json.loads(text)["errors"][0]["message"]
    assert json.loads(text)["errors"][0]["message"] == f"pile1: policy.act(): {WITHHELD}"
