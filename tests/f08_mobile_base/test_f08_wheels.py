"""Wheel model: mecanum kinematics (v_x = omega r forward, strafe, rotate) with tip-capable contacts."""

import mujoco
import numpy as np
import pytest

from rle_design.mjcf import load_design
from rle_tasks.core.solutions import materialise
from rle_tasks.f08_mobile_base.public.scene import build_scene
from rle_tasks.f08_mobile_base.public.wheels import mecanum_speeds


@pytest.mark.parametrize("twist", [(0.4, 0.0, 0.0), (0.0, 0.4, 0.0), (0.0, 0.0, 0.8)])
def test_mecanum_twist_is_reproduced(twist):
    # Mecanum inverse kinematics omega_i = sqrt2 (v_i . s_i) / r must give back the commanded twist.
    sc = build_scene(load_design(materialise("08-mobile-base", "reference")).fresh_spec)
    m, d = sc.model, sc.rest_data()
    ids = [
        mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, w)
        for w in ("wheel_fl", "wheel_fr", "wheel_rl", "wheel_rr")
    ]
    xy = np.array([d.xpos[i][:2] for i in ids])
    for _ in range(600):
        d.ctrl[sc.wheel_act] = mecanum_speeds(*twist, xy)
        mujoco.mj_step(m, d)
    rot = d.xmat[sc.chassis].reshape(3, 3)
    v_body = rot.T @ d.qvel[:3]
    np.testing.assert_allclose([v_body[0], v_body[1], d.qvel[5]], twist, atol=0.05 * max(twist) + 0.01)


def test_only_wheels_touch_the_floor_and_they_share_the_weight():
    sc = build_scene(load_design(materialise("08-mobile-base", "reference")).fresh_spec)
    d = sc.rest_data()
    for _ in range(400):
        mujoco.mj_step(sc.model, d)
    from rle_design.stability import sample_contacts

    s = sample_contacts(sc.model, d, sc.probe.supports)
    assert s.normal.sum() == pytest.approx(sc.mass * 9.81, rel=0.02)
    assert np.all(s.normal > 0.1 * sc.mass * 9.81 / 4)


def test_reference_controller_uses_the_documented_wheel_convention(tmp_path):
    # The controller may not import rle_tasks; its copy of the convention must equal the verifier's.
    import importlib.util

    ref = materialise("08-mobile-base", "reference", dest=tmp_path / "ref")  # own copy: import writes caches
    spec = importlib.util.spec_from_file_location("ref_ctl", ref / "controller.py")
    ctl = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ctl)
    xy = np.array([[0.28, 0.25], [0.28, -0.25], [-0.28, 0.25], [-0.28, -0.25]])
    for twist in [(0.3, 0.0, 0.0), (0.0, -0.2, 0.0), (0.1, 0.2, 0.7)]:
        np.testing.assert_allclose(ctl.mecanum_speeds(*twist, xy), mecanum_speeds(*twist, xy), atol=1e-12)
