"""Catalog robots: constants point at files that exist, name real joints and actuators, keyframes compile."""

import mujoco
import numpy as np
import pytest

from rle_design.catalog import load_catalog
from rle_design.errors import ConfigError, MjcfError
from rle_design.scene import TOOL_SITE, RobotConstants, arm_ids, element_id, load_robot, robot_constants


def test_arm_list_is_the_catalog():
    assert arm_ids() == tuple(e.id for e in load_catalog("arms"))
    assert len(arm_ids()) >= 3


@pytest.mark.parametrize("arm", arm_ids())
def test_constants_match_the_model(arm):
    c = robot_constants(arm)
    entry = load_catalog("arms").get(arm)
    assert c.id == arm and c.dof == entry.dof
    assert c.model_path.is_file() and c.root_body == entry.root_body and c.tool_body == entry.tool_body
    m = load_robot(arm, keyframes=False).compile()
    assert m.body_subtreemass[0] == pytest.approx(entry.mass, abs=1e-3)  # catalog mass = model mass
    element_id(m, "body", c.root_body)
    for k, (joint, act, limit) in enumerate(zip(c.joints, c.actuators, c.torque_limits)):
        j = element_id(m, "joint", joint)
        assert m.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE and m.jnt_qposadr[j] == k
        a = element_id(m, "actuator", act)
        assert m.actuator_trnid[a, 0] == j
        np.testing.assert_array_equal(m.actuator_ctrlrange[a], [-limit, limit])
    tool = element_id(m, "site", TOOL_SITE)
    assert m.site_bodyid[tool] == element_id(m, "body", c.tool_body)
    np.testing.assert_array_equal(m.site_pos[tool], [0.0, 0.0, 0.0])


@pytest.mark.parametrize("arm", arm_ids())
def test_keyframes_compile_inside_the_limits_and_step_without_warnings(arm):
    c = robot_constants(arm)
    m = load_robot(arm).compile()
    assert m.nkey == 2
    for name, qpos in (("home", c.home), ("stowed", c.stowed)):
        key = element_id(m, "keyframe", name)
        np.testing.assert_array_equal(m.key_qpos[key], qpos)
        lo, hi = m.jnt_range[:, 0], m.jnt_range[:, 1]
        assert np.all((lo <= m.key_qpos[key]) & (m.key_qpos[key] <= hi)), name
        d = mujoco.MjData(m)
        mujoco.mj_resetDataKeyframe(m, d, key)
        mujoco.mj_step(m, d, int(1.0 / m.opt.timestep))
        assert np.isfinite(d.qpos).all() and all(w.number == 0 for w in d.warning)


def test_unknown_arm_lists_the_catalog():
    with pytest.raises(MjcfError) as err:
        load_robot("kuka")
    assert str(err.value) == f"unknown arm 'kuka'. Available arms: {', '.join(arm_ids())}"
    assert err.value.code == "arm.unknown"


def test_constants_must_give_one_value_per_joint():
    with pytest.raises(ConfigError) as err:
        RobotConstants("two", ("a", "b"), (0.0, 0.0), (0.0,), ("m1", "m2"), (1.0, 1.0), "test")
    assert str(err.value) == "RobotConstants 'two': stowed has 1 entries for 2 joints"
