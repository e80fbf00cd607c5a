"""Development workspaces of family 01: the harness of each level, and the served session's levels."""

import numpy as np
import pytest

from rle_design.ledger import LedgerClient, LedgerError
from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.devenv import layout_workspace
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret

PUBLIC = Secret(PUBLIC_KEY, public=True)


@pytest.mark.parametrize(
    "level,modules",
    [
        (1, {"robot"}),
        (2, {"robot", "geometry", "perception", "motion"}),
        (3, {"robot", "geometry", "perception", "motion", "world"}),
    ],
)
def test_workspace_lays_out_the_level_s_harness(tmp_path, level, modules):
    ws = layout_workspace(get_task(f"01-open-fridge-l{level}"), tmp_path / "ws", serve=False, secret=PUBLIC)
    harness = {
        f.split("/")[1][:-3] for f in ws.files if f.startswith("harness/") and f != "harness/__init__.py"
    }
    assert harness == modules
    assert {"instruction.md", "client.py"} <= set(ws.files)
    client = (tmp_path / "ws" / "client.py").read_text()
    assert "an action of 12 values" in client and "reset(evaluation=True)" in client
    for module in (tmp_path / "ws" / "harness").glob("*.py"):  # public modules import only the toolkit
        assert "rle_tasks" not in module.read_text(), module.name
    assert f"harness L{level}" in (tmp_path / "ws" / "instruction.md").read_text()


@pytest.mark.physics
def test_served_session_gives_each_level_its_observation(tmp_path):
    seen = {}
    for level in (1, 2, 3):
        ws = layout_workspace(
            get_task(f"01-turn-on-stove-l{level}"),
            tmp_path / f"ws{level}",
            secret=PUBLIC,
            ledger_dir=tmp_path / f"l{level}",
        )
        try:
            with LedgerClient(ws.server.socket_path) as c:
                obs = c.reset(kitchen=3, seed=1)
                assert obs["rgb"]["robot/agentview_left"].shape == (128, 128, 3)
                assert obs["depth"]["robot/arm/eye_in_hand"].dtype == np.float32
                seen[level] = set(obs)
                if level == 1:
                    with pytest.raises(LedgerError) as exc:
                        c.query("segment", prompt="knob")
                    assert exc.value.code == "ledger.bad_request"
                else:
                    seg = c.query("segment", prompt="knob", camera="robot/agentview_left")
                    assert seg["masks"].shape[1:] == (128, 128)
                hold = np.zeros(12)
                hold[6] = hold[11] = -1.0
                c.step(hold)
                assert c.info()["development_steps"] == 2
                c.seal()
            ws.server.wait(30)
        finally:
            ws.close()
    assert {"cameras", "objects", "fixtures", "target", "grasped"}.isdisjoint(seen[1])
    assert "cameras" in seen[2] and {"objects", "fixtures", "target"}.isdisjoint(seen[2])
    assert {"cameras", "objects", "fixtures", "target", "grasped"} <= seen[3]
