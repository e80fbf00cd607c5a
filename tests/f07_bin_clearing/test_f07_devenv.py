"""Development workspace: public modules laid out, the metered session plays the same environment."""

import json

import numpy as np
import pytest

from rle_design.ledger.session import MeteredSession
from rle_tasks.core.devenv import layout_workspace
from rle_tasks.core.registry import get_task
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
