"""Sessions over many scenes: development budget, the terminal evaluation phase, and the verifier's replay
of each trial, on sliders whose motion has a closed form."""

from dataclasses import dataclass
from pathlib import Path

import pytest

from rle_design.control.replay import ReplayError
from rle_design.ledger import (
    EvaluationPhase,
    LedgerClient,
    LedgerError,
    LedgerServer,
    MeteredEnv,
    SceneSet,
    development_steps,
    replay_trials,
    verify_ledger,
)

KEY = b"k" * 32
SLIDER = """
<mujoco>
  <option timestep="0.001" gravity="0 0 0" integrator="Euler"/>
  <worldbody>
    <body name="cart">
      <joint name="x" type="slide" axis="1 0 0"/>
      <geom name="cart" type="box" size="0.1 0.1 0.1" mass="{mass}"/>
    </body>
  </worldbody>
  <actuator><motor name="push" joint="x" ctrlrange="-100 100"/></actuator>
</mujoco>
"""
MASSES = {"dev/0": 1.0, "dev/1": 2.0, "eval/0": 4.0, "eval/1": 8.0, "other/0": 4.0}
GOAL = 0.01
"""A trial succeeds once the cart is past x = 0.01 m."""


@dataclass(frozen=True)
class Sliders(SceneSet):
    """Scenes of a pushed cart that differ by mass."""

    n_substeps: int = 10
    evaluation: EvaluationPhase | None = EvaluationPhase(trials=2, actions_per_trial=3)
    eval_prefix: str = "eval"

    def scene(self, key: str) -> MeteredEnv:
        if key not in MASSES:
            raise LedgerError(f"unknown scene '{key}'", code="ledger.bad_scene")
        return MeteredEnv(xml=SLIDER.format(mass=MASSES[key]), n_substeps=self.n_substeps)

    def development_key(self, index: int, options: dict) -> str:
        return f"dev/{options.get('k', index % 2)}"

    def evaluation_key(self, trial: int) -> str:
        return f"{self.eval_prefix}/{trial}"

    def success(self, env, model, data) -> bool:
        return data.qpos[0] > GOAL


def _session(tmp_path: Path, budget: int = 100, scenes: SceneSet | None = None):
    return (scenes or Sliders()).open_session(
        task_id="t", budget=budget, key=KEY, ledger_path=tmp_path / "l.jsonl"
    )


def _records(path: Path) -> list[dict]:
    import json

    return [json.loads(line) for line in path.read_text().splitlines()]


def test_development_resets_pick_scenes_and_record_them(tmp_path):
    s = _session(tmp_path)
    s.reset()
    assert s.key == "dev/0" and s.model.body_mass[1] == 1.0
    s.reset()
    assert s.key == "dev/1" and s.model.body_mass[1] == 2.0
    s.reset({"k": 0})
    assert s.key == "dev/0"
    s.step([1.0])
    s.seal()
    resets = [r["payload"] for r in _records(tmp_path / "l.jsonl") if r["kind"] == "reset"]
    assert [(r["scene"], r["phase"]) for r in resets] == [
        ("dev/0", "development"),
        ("dev/1", "development"),
        ("dev/0", "development"),
    ]
    assert all(len(r["scene_sha256"]) == 64 for r in resets)
    assert verify_ledger(tmp_path / "l.jsonl", KEY, "t").valid
    assert development_steps(tmp_path / "l.jsonl") == 4


def test_budget_limits_development_only(tmp_path):
    s = _session(tmp_path, budget=3)
    s.reset()
    s.step([0.0])
    s.step([0.0])
    with pytest.raises(LedgerError) as exc:
        s.step([0.0])
    assert exc.value.code == "ledger.budget_exhausted"
    with pytest.raises(LedgerError):
        s.reset()
    s.reset({"evaluation": True})
    for _ in range(3):
        s.step([5.0])
    assert s.dev_steps == 3 and s.steps_used == 7
    assert s.info()["trials"][0]["actions"] == 3


def test_evaluation_phase_trials_and_caps(tmp_path):
    s = _session(tmp_path)
    s.reset()
    s.reset({"evaluation": True})
    assert s.key == "eval/0" and s.phase == "evaluation"
    with pytest.raises(LedgerError) as exc:
        s.reset({"evaluation": True})
    assert exc.value.code == "ledger.bad_request"
    for _ in range(3):
        s.step([10.0])
    with pytest.raises(LedgerError) as exc:
        s.step([10.0])
    assert exc.value.code == "ledger.trial_exhausted"
    with pytest.raises(LedgerError) as exc:
        s.reset({"k": 1})
    assert exc.value.code == "ledger.bad_request"
    s.reset()
    assert s.key == "eval/1"
    with pytest.raises(LedgerError) as exc:
        s.reset()
    assert exc.value.code == "ledger.trials_done"
    s.seal()
    seal = _records(tmp_path / "l.jsonl")[-1]["payload"]
    assert seal["development_steps"] == 1
    assert [t["scene"] for t in seal["trials"]] == ["eval/0", "eval/1"]
    assert [t["actions"] for t in seal["trials"]] == [3, 0]


def test_replay_decides_each_trial_with_the_closed_form_motion(tmp_path):
    """Force F on mass m from rest, semi-implicit Euler at dt: x after n steps = F dt^2 n (n + 1) / (2 m).
    Trial 0 (m = 4 kg, F = 100 N, 10 steps per action): 1.375 mm, 5.25 mm, 11.625 mm after 1, 2, 3 actions:
    success (x > 1 cm) at action 3. Trial 1 (m = 8 kg, F = 10 N): 0.58 mm after 3 actions, no success."""
    s = _session(tmp_path)
    s.reset({"evaluation": True})
    for _ in range(3):
        s.step([100.0])
    x = float(s.data.qpos[0])
    n = 30
    assert x == pytest.approx(100.0 * 1e-6 * n * (n + 1) / (2 * 4.0), rel=1e-9)
    s.reset()
    for _ in range(3):
        s.step([10.0])
    s.seal()
    trials = replay_trials(Sliders(), tmp_path / "l.jsonl")
    assert [(t.trial, t.scene, t.actions, t.success_at) for t in trials] == [
        (0, "eval/0", 3, 3),
        (1, "eval/1", 3, None),
    ]
    assert [t.recorded_success for t in trials] == [True, False]


def test_replay_refuses_other_scenes(tmp_path):
    s = _session(tmp_path)
    s.reset({"evaluation": True})
    s.step([1.0])
    s.seal()
    with pytest.raises(ReplayError) as exc:
        replay_trials(Sliders(eval_prefix="other"), tmp_path / "l.jsonl")
    assert exc.value.code == "replay.other_scene"


def test_served_scene_set_over_the_socket(tmp_path):
    server = LedgerServer(
        Sliders(),
        key=KEY,
        ledger_path=tmp_path / "l.jsonl",
        socket_path=tmp_path / "s.sock",
        task_id="t",
        budget=10,
    )
    server.start()
    try:
        with LedgerClient(server.socket_path) as c:
            c.reset(k=1)
            assert c.info()["scene"] == "dev/1"
            c.reset(evaluation=True)
            c.step([100.0])
            info = c.info()
            assert info["phase"] == "evaluation" and info["trials"][0]["actions"] == 1
            with pytest.raises(LedgerError) as exc:
                c.query("nothing")
            assert exc.value.code == "ledger.bad_request"
            c.seal()
        server.wait(30)
    finally:
        server.stop()
    assert verify_ledger(tmp_path / "l.jsonl", KEY, "t").valid


def test_single_scene_sessions_refuse_reset_options(tmp_path):
    from rle_design.ledger import MeteredSession

    s = MeteredSession(MeteredEnv(xml=SLIDER.format(mass=1.0)), task_id="t", budget=5)
    with pytest.raises(LedgerError) as exc:
        s.reset({"evaluation": True})
    assert exc.value.code == "ledger.bad_request"
