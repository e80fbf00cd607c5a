"""Shelf trials: a controller's wrong shape or non-finite command is a participant fault with its code."""

from pathlib import Path

import numpy as np
import pytest

from rle_design.mjcf import load_design
from rle_design.sandbox import ParticipantFault, Sandbox, SandboxLimits
from rle_tasks.core.solutions import materialise
from rle_tasks.f08_mobile_base.env import layout, run_trial
from rle_tasks.f08_mobile_base.public.scene import build_scene

BODY = """import numpy as np
def reset(arm, target, payload_kg, layout):
    global NU
    NU = len(layout["actuators"])
def control(t, qpos, qvel, ctrl):
    return {ret}
"""


@pytest.fixture(scope="module")
def scene():
    return build_scene(
        load_design(materialise("08-mobile-base", "reference")).fresh_spec, "xarm7", 1, shelf=True
    )


@pytest.mark.parametrize(
    ("ret", "code"),
    [("np.zeros(3)", "sandbox.bad_shape"), ("np.full(NU, np.nan)", "sandbox.non_finite")],
)
def test_bad_command_is_a_participant_fault(tmp_path: Path, scene, ret, code):
    (tmp_path / "controller.py").write_text(BODY.format(ret=ret))
    limits = SandboxLimits(call_timeout_s=30.0)
    with (
        Sandbox(str(tmp_path / "controller.py"), limits=limits) as sb,
        pytest.raises(ParticipantFault) as err,
    ):
        run_trial(scene, sb, np.array([1.2, 0.0, 0.8]), 1.0)
    assert err.value.code == code
    assert "control" in err.value.message


def test_layout_names_every_actuator_once(scene):
    lay = layout(scene)
    assert len(lay["actuators"]) == scene.model.nu
    assert sorted(lay["wheel_actuators"] + lay["arm_actuators"]) == list(range(scene.model.nu))
    assert lay["wheel_joints"] == ["wheel_fl_spin", "wheel_fr_spin", "wheel_rl_spin", "wheel_rr_spin"]


def test_idle_controller_times_out_without_success(tmp_path: Path, scene):
    # A finite, well-shaped command that does nothing: the trial ends at the episode limit, not held.
    (tmp_path / "controller.py").write_text(BODY.format(ret="np.zeros(NU)"))
    with Sandbox(str(tmp_path / "controller.py"), limits=SandboxLimits(call_timeout_s=30.0)) as sb:
        r = run_trial(scene, sb, np.array([1.2, 0.0, 0.8]), 1.0)
    assert not r["success"]
    assert r["reason"].startswith(("timeout", "tipping", "sustained loss"))
