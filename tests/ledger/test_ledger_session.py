"""Metered sessions over the server process: budget, free observations, a clean 10,000-step ledger."""

from __future__ import annotations

from multiprocessing.connection import Client

import numpy as np
import pytest

from rle_design.ledger import (
    LedgerClient,
    LedgerError,
    LedgerServer,
    MeteredEnv,
    MeteredSession,
    verify_ledger,
)

KEY = b"ledger-session-key-0123456789abc"
TASK = "09-gello"
# A point mass on a slider driven by a force motor: a = u / m with m = 2 kg, no gravity along x.
SLIDER = """
<mujoco>
  <option timestep="0.002" gravity="0 0 0"/>
  <worldbody>
    <body name="cart">
      <joint name="x" type="slide" axis="1 0 0"/>
      <geom type="sphere" size="0.05" mass="2"/>
    </body>
  </worldbody>
  <actuator><motor name="push" joint="x"/></actuator>
</mujoco>
"""


def cart_speed(model, data) -> float:
    """Extra observer (module level so the spawned server can import it)."""
    return float(data.qvel[0])


@pytest.fixture()
def server(tmp_path):
    env = MeteredEnv(SLIDER, n_substeps=10, observers=(("speed", cart_speed),))
    srv = LedgerServer(
        env,
        key=KEY,
        ledger_path=tmp_path / "ledger.jsonl",
        socket_path=tmp_path / "ledger.sock",
        task_id=TASK,
        budget=10_001,
    )
    srv.start()
    yield srv
    srv.stop()


def test_clean_10000_step_session_verifies(server):
    with LedgerClient(server.socket_path) as env:
        obs = env.reset()
        assert obs["qpos"].tolist() == [0.0] and obs["time"] == 0.0
        u = np.array([4.0])
        for _ in range(10_000):
            obs = env.step(u)
        # constant force from rest: v = (u / m) t = 2 m/s^2 * t, with t = 10,000 * 10 * 0.002 s = 200 s
        assert obs["time"] == pytest.approx(200.0)
        assert obs["speed"] == pytest.approx(2.0 * 200.0, rel=1e-9)
        assert env.steps_used == 10_001
        head = env.seal()
    server.wait(10)
    verdict = verify_ledger(server.ledger_path, KEY, task_id=TASK)
    assert verdict.valid, verdict.message
    assert verdict.steps == 10_001 and verdict.head == head


def test_budget_exhausted_observations_free_and_sealed_on_stop(tmp_path):
    env = MeteredEnv(SLIDER, n_substeps=2)
    srv = LedgerServer(
        env,
        key=KEY,
        ledger_path=tmp_path / "l.jsonl",
        socket_path=tmp_path / "s.sock",
        task_id=TASK,
        budget=3,
    )
    with srv, LedgerClient(srv.socket_path) as client:
        client.reset()
        client.step([1.0])
        for _ in range(5):
            client.observe()  # free
        assert client.info()["steps_used"] == 2
        client.step([1.0])
        with pytest.raises(LedgerError) as info:
            client.step([1.0])
        assert info.value.code == "ledger.budget_exhausted"
        assert f"{info.value.code}: {info.value}".startswith("ledger.budget_exhausted: 3 of 3 steps used")
        with pytest.raises(LedgerError) as info:
            client.reset()
        assert info.value.code == "ledger.budget_exhausted"
    verdict = verify_ledger(tmp_path / "l.jsonl", KEY, TASK)  # sealed by stop()
    assert verdict.valid and verdict.steps == 3


def test_bad_actions_and_malformed_requests_are_refused_uncharged(server):
    with LedgerClient(server.socket_path) as client:
        client.reset()
        with pytest.raises(LedgerError) as info:
            client.step(np.zeros(3))
        assert info.value.code == "ledger.bad_action"
        assert str(info.value) == "action must be 1 real numbers (the actuators' ctrl), got shape (3,)"
        with pytest.raises(LedgerError) as info:
            client.step([float("nan")])
        assert str(info.value) == "action holds NaN or infinity"
        with pytest.raises(LedgerError) as info:
            client.step("left")
        assert info.value.code == "ledger.bad_action"
        assert client.info()["steps_used"] == 1
    raw = Client(str(server.socket_path), family="AF_UNIX")
    raw.send_bytes(b"\x80\x04pickle bomb")  # never unpickled: a malformed frame
    from rle_design.ledger.server import decode

    meta, _ = decode(raw.recv_bytes())
    assert meta == {
        "ok": False,
        "code": "ledger.bad_request",
        "message": "malformed request: message shorter than the frame prefix",
    }
    raw.close()
    with LedgerClient(server.socket_path) as client:  # the server survives
        assert client.info()["steps_used"] == 1


def test_unmetered_session_writes_nothing_and_budget_message(tmp_path):
    session = MeteredSession(MeteredEnv(SLIDER), task_id=TASK, budget=1)
    session.reset()
    with pytest.raises(LedgerError) as info:
        session.step([0.0])
    assert str(info.value) == (
        "1 of 1 steps used; resets and executed actions cost one step each, observations are free"
    )
    assert session.seal() == "" and list(tmp_path.iterdir()) == []


def test_unknown_keyframe_and_bad_model():
    with pytest.raises(LedgerError) as info:
        MeteredSession(MeteredEnv(SLIDER, keyframe="home"), task_id=TASK, budget=None)
    assert str(info.value) == "keyframe 'home' does not exist. Available keyframes: (none)"
    with pytest.raises(LedgerError) as info:
        MeteredSession(MeteredEnv("<mujoco><bogus/></mujoco>"), task_id=TASK, budget=None)
    assert info.value.code == "ledger.bad_model"


def test_client_without_server(tmp_path):
    with pytest.raises(LedgerError) as info:
        LedgerClient(tmp_path / "nobody.sock")
    assert info.value.code == "ledger.no_server"


def broken_observer(model, data) -> float:
    """An observer with a bug: the server reports it and keeps serving."""
    raise RuntimeError("observer bug")


def test_a_failing_observer_does_not_end_the_session(tmp_path):
    env = MeteredEnv(SLIDER, observers=(("bad", broken_observer),))
    srv = LedgerServer(
        env,
        key=KEY,
        ledger_path=tmp_path / "l.jsonl",
        socket_path=tmp_path / "s.sock",
        task_id=TASK,
        budget=None,
    )
    with srv, LedgerClient(srv.socket_path) as client:
        with pytest.raises(LedgerError) as info:
            client.observe()
        assert info.value.code == "ledger.internal"
        assert str(info.value) == "server error: RuntimeError: observer bug"
        assert client.info()["steps_used"] == 0


def test_wall_time_limit_refuses_steps_and_is_recorded(tmp_path, monkeypatch):
    from rle_design.ledger import session as session_mod

    clock = [100.0]
    monkeypatch.setattr(session_mod.time, "monotonic", lambda: clock[0])
    path = tmp_path / "ledger.jsonl"
    s = MeteredSession(
        MeteredEnv(SLIDER), task_id=TASK, budget=None, key=KEY, ledger_path=path, wall_time_s=60.0
    )
    s.reset()
    clock[0] += 60.0  # exactly at the limit: still allowed
    s.step(np.array([1.0]))
    clock[0] += 0.5
    with pytest.raises(LedgerError) as err:
        s.step(np.array([1.0]))
    assert err.value.code == "ledger.time_exhausted" and "60 s are over" in str(err.value)
    assert s.steps_used == 2 and s.observe()["time"] > 0  # observations still free
    s.seal()
    verdict = verify_ledger(path, KEY, TASK)
    assert verdict.valid and verdict.steps == 2
    assert verdict.opened["wall_time_s"] == 60.0 and verdict.sealed["elapsed_s"] == 60.5
    with pytest.raises(ValueError):
        MeteredSession(MeteredEnv(SLIDER), task_id=TASK, budget=None, wall_time_s=0.0)


def test_a_session_without_wall_limit_records_no_time_fields(tmp_path):
    path = tmp_path / "ledger.jsonl"
    s = MeteredSession(MeteredEnv(SLIDER), task_id=TASK, budget=None, key=KEY, ledger_path=path)
    s.reset()
    s.seal()
    verdict = verify_ledger(path, KEY, TASK)
    assert "wall_time_s" not in verdict.opened and "elapsed_s" not in verdict.sealed


def test_record_session_replaces_a_ledger_only_once_sealed(tmp_path):
    """``record_session``: a recording that fails leaves the ledger already there untouched; one that
    succeeds replaces it with a sealed ledger of its own actions (v = u t / m after 10 x 0.002 s of 1 N)."""
    from rle_design.ledger import record_session

    ledger = tmp_path / "shipped" / "ledger.jsonl"
    ledger.parent.mkdir()
    ledger.write_text("the shipped ledger\n")

    def broken(client):
        client.reset()
        raise RuntimeError("the program failed")

    with pytest.raises(RuntimeError, match="the program failed"):
        record_session(MeteredEnv(SLIDER), broken, ledger, key=KEY, task_id=TASK, budget=10)
    assert ledger.read_text() == "the shipped ledger\n"
    speeds = []

    def push(client):
        client.reset()
        speeds.append(client.step(np.array([1.0]))["qvel"][0])

    assert record_session(MeteredEnv(SLIDER), push, ledger, key=KEY, task_id=TASK, budget=10) == ledger
    assert verify_ledger(ledger, KEY, TASK).valid
    assert speeds[0] == pytest.approx(1.0 * 10 * 0.002 / 2.0)
    assert sorted(p.name for p in ledger.parent.iterdir()) == ["ledger.jsonl"]
