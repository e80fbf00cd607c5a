"""Development workspace: public modules laid out, the metered session plays the same environment."""

import json

import numpy as np
import pytest

from rle_design.ledger.session import MeteredSession
from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.devenv import layout_workspace
from rle_tasks.f07_bin_clearing.public.env import make_env
from rle_tasks.f07_bin_clearing.public.pile import PUBLIC_SEEDS, PileSpec


def test_workspace_has_the_public_package_and_a_client(tmp_path):
    ws = layout_workspace(get_task("07-bin-clearing"), tmp_path / "ws", serve=False)
    for f in ("bin_clearing/workcell.py", "bin_clearing/env.py", "bin_clearing/devrun.py", "client.py",
              "calibration.json"):  # fmt: skip
        assert f in ws.files, f
    for module in (tmp_path / "ws" / "bin_clearing").glob("*.py"):  # they import only rle_design
        assert "rle_tasks" not in module.read_text(), module.name


def test_committed_calibration_is_the_workcell_s():
    from rle_tasks.f07_bin_clearing.public.workcell import calibration
    from rle_tasks.f07_bin_clearing.task import CALIBRATION

    assert json.loads(CALIBRATION.read_text()) == json.loads(json.dumps(calibration()))


@pytest.mark.physics
def test_metered_session_observes_what_the_policy_sees(tmp_path):
    env = make_env(PileSpec.public(PUBLIC_SEEDS[0]))
    session = MeteredSession(env, task_id="07-bin-clearing", budget=None)
    obs = session.reset()
    assert {"time", "q", "dq", "tau", "ft", "magnet", "nest", "overhead", "wrist"} <= set(obs)
    assert "qpos" not in obs  # part poses are withheld
    assert obs["overhead"]["depth"].shape == (240, 320) and obs["wrist"]["rgb"].shape == (120, 160, 3)
    obs = session.step(np.concatenate([obs["q"], [0.0]]))
    assert obs["time"] == pytest.approx(0.05) and "overhead" not in obs  # images at 10 Hz
    obs = session.step(np.concatenate([obs["q"], [0.0]]))
    assert "overhead" in obs and session.steps_used == 3


OBJECT_POLICY = """
import numpy as np


class Policy:
    pass


def make_policy():
    return Policy()


def reset():
    return None


def act(obs):
    return np.concatenate([obs["q"], [0.0]])
"""


def test_devrun_refuses_what_the_verifier_refuses_with_the_same_code(tmp_path, capsys):
    from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
    from rle_tasks.core.task import VerifyContext
    from rle_tasks.f07_bin_clearing.public import devrun
    from rle_tasks.f07_bin_clearing.verifier import verify

    (tmp_path / "policy").mkdir()
    (tmp_path / "policy" / "__init__.py").write_text(OBJECT_POLICY)
    with pytest.raises(SystemExit) as stop:
        devrun.main([str(tmp_path / "policy"), "--seconds", "0.1"])
    assert stop.value.code == 2
    said = capsys.readouterr().err
    assert "sandbox.bad_type: policy.make_policy(): «cannot return value of type Policy" in said
    report = verify(
        tmp_path, VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True, hang_cap_s=5.0)
    )
    assert [(e.code, e.message) for e in report.errors] == [
        ("sandbox.bad_type", "policy could not be loaded: " + said.split("sandbox.bad_type: ")[1].strip())
    ]


@pytest.mark.physics
def test_devrun_prints_the_event_timeline_and_writes_both_cameras(tmp_path, capsys):
    from rle_tasks.core.registry import get_task
    from rle_tasks.core.solutions import materialise
    from rle_tasks.f07_bin_clearing.public import devrun

    policy = materialise(get_task("07-bin-clearing"), "reference") / "policy"
    devrun.main([str(policy), "--seed", "101", "--seconds", "14", "--events", "--frames", str(tmp_path)])
    out = capsys.readouterr().out
    lines = [ln for ln in out.splitlines() if " s  " in ln]
    kinds = [ln.split()[2] for ln in lines]
    assert "delivered" in kinds and "cleared" in kinds, out
    assert kinds.index("delivered") < kinds.index("cleared")
    times = [float(ln.split()[0]) for ln in lines]
    assert times == sorted(times)
    summary = json.loads(out[out.index("{") :])
    assert summary["cleared"] == kinds.count("cleared") and "timeline" not in summary
    assert len(list(tmp_path.glob("overhead_*.png"))) == len(list(tmp_path.glob("wrist_*.png"))) == 28
