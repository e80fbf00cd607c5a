"""The policy runner (submitted Python under a declared protocol) and the ONNX policy loader."""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pytest

from rle_design.errors import MissingElement, RleError
from rle_design.sandbox import ParticipantFault
from rle_tasks.core.runtime.policy import PolicyFault, PolicyRunner, distinct
from rle_tasks.core.runtime.protocol import Budget, FunctionSpec, Protocol

PROTOCOL = Protocol(
    module="policy",
    functions=(
        FunctionSpec("act", "x: (n,)", returns=("n",), timeout_s=10.0),
        FunctionSpec("info", "()", returns=None, finite=False),
        FunctionSpec("nope", "()"),
    ),
)

# act(x) = 2 x + 1 with a per-process call counter in info(); x[0] selects a misbehaviour.
GOOD = """import numpy as np
_calls = [0]
def act(x):
    _calls[0] += 1
    x = np.asarray(x, dtype=float)
    if x[0] == -1:
        raise RuntimeError("boom")
    if x[0] == -2:
        return np.zeros(len(x) + 1)
    if x[0] == -3:
        return np.full(len(x), np.nan)
    if x[0] == -4:
        while True:
            pass
    return 2.0 * x + 1.0
def info():
    return {"calls": _calls[0], "inf": float("inf")}
"""


def _runner(tmp_path: Path, body: str = GOOD, **kw) -> PolicyRunner:
    (tmp_path / "policy.py").write_text(body)
    return PolicyRunner(tmp_path / "policy.py", PROTOCOL, dims={"n": 3}, **kw)


def test_good_submission_returns_exact_outputs_from_one_child(tmp_path):
    with _runner(tmp_path) as run:
        assert np.array_equal(run.call("act", np.array([1.0, 2.0, 3.0])), [3.0, 5.0, 7.0])
        assert np.array_equal(run.call("act", [0.5, 0.0, -0.5]), [2.0, 1.0, 0.0])
        assert run.call("info") == {"calls": 2, "inf": float("inf")}  # finite=False declared
        assert run.alive and run.restarts == 0 and not run.faults and not run.exhausted
        assert run.missing() == ["nope"]
        assert 0.0 < run.cpu_used_s < 10.0
    assert not run.alive


@pytest.mark.parametrize(
    ("x0", "code", "text"),
    [
        (-1.0, "sandbox.exception", "policy.act(): «RuntimeError: boom»"),
        (-2.0, "sandbox.bad_shape", "policy.act(): expected shape (3,), got «(4,)»"),
        (-3.0, "sandbox.non_finite", "policy.act(): output holds 3 non-finite value(s) (NaN or inf)"),
    ],
)
def test_fault_is_raised_recorded_and_the_next_call_restarts(tmp_path, x0, code, text):
    with _runner(tmp_path) as run:
        run.call("act", [1.0, 1.0, 1.0])
        with pytest.raises(ParticipantFault) as err:
            run.call("act", [x0, 0.0, 0.0])
        assert (err.value.code, err.value.message) == (code, text)
        assert not run.alive  # closed after the fault
        assert run.call("info")["calls"] == 0  # a fresh child: module state starts over
        assert run.restarts == 1 and run.n_faults == 1 and not run.exhausted
        assert [(f.function, f.code, f.message) for f in run.faults] == [("act", code, text)]


def test_fault_budget_refuses_further_calls_without_a_child(tmp_path):
    with _runner(tmp_path, budget=Budget(max_faults=2)) as run:
        assert run.try_call("act", [-1.0, 0.0, 0.0]) is None
        assert run.try_call("act", [-1.0, 0.0, 0.0]) is None
        assert run.exhausted and run.restarts == 1
        with pytest.raises(PolicyFault) as err:
            run.call("act", [1.0, 1.0, 1.0])
        assert err.value.code == "policy.fault_budget"
        assert err.value.message == (
            "policy.act(): not called: the fault budget of 2 faults is used up (last: sandbox.exception)"
        )
        assert isinstance(err.value, ParticipantFault) and not run.alive and run.restarts == 1
        assert run.n_faults == 2 and [f.code for f in run.faults][-1] == "policy.fault_budget"
        assert [f.message for f in distinct(run.faults)] == [
            "policy.act(): «RuntimeError: boom»",
            err.value.message,
        ]


def test_hang_is_capped_by_the_hang_cap_and_ends_the_run(tmp_path):
    with _runner(tmp_path, hang_cap_s=1.0) as run:
        with pytest.raises(ParticipantFault) as err:
            run.call("act", [-4.0, 0.0, 0.0])  # declared 10 s, capped at 1 s
        assert err.value.code == "sandbox.timeout"
        assert err.value.message == "policy.act(): no reply within 1 s; the child was killed"
        assert run.exhausted and run.n_faults == 1  # not retried, whatever the fault budget
        with pytest.raises(PolicyFault, match=r"a hang \(sandbox.timeout\) ended the run"):
            run.call("info")
        assert run.restarts == 0


def test_without_restarts_a_dead_child_answers_every_later_call(tmp_path):
    budget = Budget(max_faults=None, restart=False)
    with _runner(tmp_path, hang_cap_s=1.0, budget=budget) as run:
        assert run.try_call("act", [-1.0, 0.0, 0.0]) is None
        assert run.call("info")["calls"] == 1  # an exception keeps the child and its state
        assert run.try_call("act", [-4.0, 0.0, 0.0]) is None
        assert run.try_call("info") is None
    assert [f.code for f in run.faults] == ["sandbox.exception", "sandbox.timeout", "sandbox.dead"]
    assert run.faults[-1].message == "policy.info(): the sandbox is dead (timed out after 1 s)"
    assert run.restarts == 0 and not run.exhausted


def test_missing_function_and_import_error(tmp_path):
    with _runner(tmp_path) as run:
        with pytest.raises(ParticipantFault) as err:
            run.call("nope")
        assert (err.value.code, err.value.message) == (
            "sandbox.missing_function",
            "policy.nope(): «no callable named 'nope'»",
        )
    with _runner(tmp_path, body="raise ImportError('no torch here')\n") as run:
        assert run.try_call("info") is None
        assert run.faults[0].code == "sandbox.import_error"
        assert "ImportError: no torch here" in run.faults[0].message


def test_cumulative_cpu_budget_ends_a_burner_across_restarts(tmp_path):
    # Each call burns 0.3 s of CPU then raises, so every call runs in a fresh child (about 0.5 s of
    # CPU with its start, below the >= 1 s RLIMIT_CPU each child gets); the 2 s budget is shared.
    body = (
        "import time\n"
        "def act(x):\n"
        "    t = time.process_time()\n"
        "    while time.process_time() - t < 0.3:\n"
        "        pass\n"
        "    raise RuntimeError('burnt')\n"
    )
    with _runner(tmp_path, body=body, budget=Budget(max_faults=None, cpu_s=2.0)) as run:
        codes = []
        for _ in range(12):
            try:
                run.call("act", [0.0, 0.0, 0.0])
            except ParticipantFault as exc:
                codes.append(exc.code)
            if codes[-1] == "policy.cpu_budget":
                break
    assert codes[-1] == "policy.cpu_budget" and set(codes[:-1]) == {"sandbox.exception"}
    assert 3 <= len(codes) - 1 <= 7 and run.restarts == len(codes) - 2
    assert run.cpu_used_s >= 2.0 and run.exhausted and not run.alive
    assert run.faults[-1].message.startswith("policy.act(): not called: the CPU budget of 2 s is used up")


def test_cpu_budget_is_the_child_rlimit(tmp_path):
    body = "def act(x):\n    while True:\n        pass\n"
    run = _runner(tmp_path, body=body, hang_cap_s=20.0, budget=Budget(cpu_s=1.0))
    with run, pytest.raises(ParticipantFault) as err:
        run.call("act", [0.0, 0.0, 0.0])
    assert err.value.code == "sandbox.cpu" and run.exhausted
    # rusage and the kernel's RLIMIT_CPU check sample CPU time differently: about 1 s, not exactly
    assert 0.5 <= run.cpu_used_s < 4.0


def test_declaration_errors_name_the_alternatives(tmp_path):
    with _runner(tmp_path) as run, pytest.raises(MissingElement) as err:
        run.call("reset")
    assert err.value.code == "policy.undeclared"
    assert str(err.value) == "function 'reset' does not exist. Available functions: act, info, nope"
    with pytest.raises(MissingElement) as err:
        PolicyRunner(tmp_path / "policy.py", PROTOCOL, dims={"m": 3})
    assert err.value.code == "policy.dims" and "Available dimensions: m" in str(err.value)
    with pytest.raises(ValueError, match="declares a function twice"):
        Protocol("p", (FunctionSpec("a", ""), FunctionSpec("a", "")))
    with pytest.raises(ValueError, match="not a size, a symbol or None"):
        FunctionSpec("a", "", returns=(1.5,))


def test_policy_fault_codes_and_pickling():
    fault = PolicyFault("onnx.shape", "m.onnx: bad", path="m.onnx")
    back = pickle.loads(pickle.dumps(fault))
    assert isinstance(back, PolicyFault) and (back.code, back.message, back.path) == (
        "onnx.shape",
        "m.onnx: bad",
        "m.onnx",
    )
    with pytest.raises(ValueError, match="unknown policy fault code 'onnx.nope'"):
        PolicyFault("onnx.nope", "x")
    assert isinstance(fault, RleError)


# -- ONNX ----------------------------------------------------------------------------------------------
onnx = pytest.importorskip("onnx")
pytest.importorskip("onnxruntime")
from onnx import TensorProto, helper  # noqa: E402

from rle_tasks.core.runtime.onnx_policy import OnnxSignature, TensorSpec, load_onnx_policy  # noqa: E402

W = np.array([[1.0, -2.0], [0.5, 0.0], [3.0, 1.0]], dtype=np.float32)  # (3, 2)
B = np.array([0.25, -1.0], dtype=np.float32)
SIG = OnnxSignature(
    inputs=(TensorSpec("obs", (1, "n_obs")),),
    outputs=(TensorSpec("action", (1, "n_act")),),
    max_bytes=4096,
    timeout_s=0.5,
)
DIMS = {"n_obs": 3, "n_act": 2}


def _gemm(path: Path, *, in_name: str = "obs", b: np.ndarray = B) -> Path:
    """action = obs @ W + B, a (1, 3) -> (1, 2) linear policy."""
    graph = helper.make_graph(
        [helper.make_node("Gemm", [in_name, "W", "B"], ["action"])],
        "policy",
        [helper.make_tensor_value_info(in_name, TensorProto.FLOAT, [1, 3])],
        [helper.make_tensor_value_info("action", TensorProto.FLOAT, [1, 2])],
        [
            helper.make_tensor("W", TensorProto.FLOAT, list(W.shape), W.ravel().tolist()),
            helper.make_tensor("B", TensorProto.FLOAT, [2], np.asarray(b).tolist()),
        ],
    )
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)])
    path.write_bytes(model.SerializeToString())
    return path


def _loop(path: Path) -> Path:
    """A model that adds 1 to its input 10^12 times (never finishes in time)."""
    body = helper.make_graph(
        [
            helper.make_node("Identity", ["c_in"], ["c_out"]),
            helper.make_node("Add", ["v_in", "one"], ["v_out"]),
        ],
        "body",
        [
            helper.make_tensor_value_info("i", TensorProto.INT64, []),
            helper.make_tensor_value_info("c_in", TensorProto.BOOL, []),
            helper.make_tensor_value_info("v_in", TensorProto.FLOAT, [1, 2]),
        ],
        [
            helper.make_tensor_value_info("c_out", TensorProto.BOOL, []),
            helper.make_tensor_value_info("v_out", TensorProto.FLOAT, [1, 2]),
        ],
        [helper.make_tensor("one", TensorProto.FLOAT, [1], [1.0])],
    )
    graph = helper.make_graph(
        [
            helper.make_node("Slice", ["obs", "s0", "s1", "ax"], ["start"]),
            helper.make_node("Loop", ["M", "c", "start"], ["action"], body=body),
        ],
        "hang",
        [helper.make_tensor_value_info("obs", TensorProto.FLOAT, [1, 3])],
        [helper.make_tensor_value_info("action", TensorProto.FLOAT, [1, 2])],
        [
            helper.make_tensor("M", TensorProto.INT64, [], [10**12]),
            helper.make_tensor("c", TensorProto.BOOL, [], [True]),
            helper.make_tensor("s0", TensorProto.INT64, [1], [0]),
            helper.make_tensor("s1", TensorProto.INT64, [1], [2]),
            helper.make_tensor("ax", TensorProto.INT64, [1], [1]),
        ],
    )
    path.write_bytes(
        helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)]).SerializeToString()
    )
    return path


def _load_fault(path: Path, root: Path, sig: OnnxSignature = SIG, dims=DIMS) -> PolicyFault:
    with pytest.raises(PolicyFault) as err:
        load_onnx_policy(path, root, sig, dims)
    return err.value


def test_onnx_linear_policy_gives_the_closed_form_action(tmp_path):
    _gemm(tmp_path / "policy.onnx")
    policy = load_onnx_policy("policy.onnx", tmp_path, SIG, DIMS)
    out = policy.run({"obs": [[1.0, 2.0, -1.0]]})
    # [1 + 2*0.5 - 3 + 0.25, -2 + 0 - 1 - 1]: every term exact in float32
    assert set(out) == {"action"} and out["action"].dtype == np.float64
    assert np.array_equal(out["action"], [[-0.75, -4.0]])
    assert policy.path == "policy.onnx"
    with pytest.raises(RleError, match=r"input 'obs' has shape \(1, 4\); declared \(1, 3\)"):
        policy.run({"obs": np.zeros((1, 4))})  # the verifier's own mistake, not a participant fault


def test_onnx_nonfinite_output_is_a_fault(tmp_path):
    _gemm(tmp_path / "nan.onnx", b=np.array([np.nan, 0.0], dtype=np.float32))
    policy = load_onnx_policy("nan.onnx", tmp_path, SIG, DIMS)
    with pytest.raises(PolicyFault) as err:
        policy.run({"obs": np.zeros((1, 3))})
    assert (err.value.code, err.value.message) == (
        "onnx.nonfinite",
        "nan.onnx: output 'action' holds 1 non-finite value(s) (NaN or inf)",
    )


def test_onnx_signature_and_shape_are_checked_at_load(tmp_path):
    _gemm(tmp_path / "named.onnx", in_name="observation")
    fault = _load_fault(tmp_path / "named.onnx", tmp_path)
    assert (fault.code, fault.message) == (
        "onnx.signature",
        "named.onnx: input names ['observation']; expected ['obs']",
    )
    _gemm(tmp_path / "policy.onnx")
    fault = _load_fault(Path("policy.onnx"), tmp_path, dims={"n_obs": 4, "n_act": 2})
    assert (fault.code, fault.message) == (
        "onnx.shape",
        "policy.onnx: input 'obs' has shape (1, 3); expected (1, 4)",
    )


def test_onnx_untrusted_files_are_refused(tmp_path):
    sub = tmp_path / "submission"
    sub.mkdir()
    data = _gemm(sub / "policy.onnx").read_bytes()
    (sub / "cut.onnx").write_bytes(data[: len(data) // 2])
    fault = _load_fault(Path("cut.onnx"), sub)
    assert fault.code == "onnx.load" and fault.message.startswith("cut.onnx: not a valid ONNX model")
    fault = _load_fault(Path("policy.onnx"), sub, OnnxSignature(SIG.inputs, SIG.outputs, max_bytes=64))
    assert (fault.code, fault.message) == ("onnx.size", "policy.onnx: larger than the cap of 64 bytes")
    (tmp_path / "outside.onnx").write_bytes(data)
    (sub / "link.onnx").symlink_to(tmp_path / "outside.onnx")
    fault = _load_fault(Path("link.onnx"), sub)
    assert (fault.code, fault.message) == (
        "onnx.path",
        "link.onnx: resolves outside the submission directory",
    )
    assert _load_fault(Path("../outside.onnx"), sub).code == "onnx.path"
    assert _load_fault(Path("absent.onnx"), sub).code == "onnx.path"


def test_onnx_external_data_is_refused(tmp_path):
    model = onnx.load_model_from_string(_gemm(tmp_path / "policy.onnx").read_bytes())
    w = model.graph.initializer[0]
    w.ClearField("float_data")
    w.data_location = TensorProto.EXTERNAL
    entry = w.external_data.add()
    entry.key, entry.value = "location", "/etc/passwd"
    (tmp_path / "ext.onnx").write_bytes(model.SerializeToString())
    fault = _load_fault(Path("ext.onnx"), tmp_path)
    assert (fault.code, fault.message) == (
        "onnx.external_data",
        "ext.onnx: references external data files; embed every tensor",
    )


def test_onnx_inference_past_its_timeout_is_stopped(tmp_path):
    policy = load_onnx_policy(_loop(tmp_path / "hang.onnx"), tmp_path, SIG, DIMS)
    with pytest.raises(PolicyFault) as err:
        policy.run({"obs": np.zeros((1, 3))})
    assert (err.value.code, err.value.message) == ("onnx.timeout", "hang.onnx: no result within 0.5 s")


def test_onnx_without_onnxruntime_names_the_extra(tmp_path, monkeypatch):
    monkeypatch.setitem(__import__("sys").modules, "onnxruntime", None)
    with pytest.raises(RleError) as err:
        load_onnx_policy("policy.onnx", tmp_path, SIG, DIMS)
    assert (
        err.value.code == "onnx.missing_dependency" and "pip install 'rle-bench[learn]'" in err.value.message
    )
