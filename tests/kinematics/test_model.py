"""Pinocchio models from MJCF: the silently dropped constructs are flagged, kinematics match MuJoCo."""

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from rle_design.errors import MjcfError
from rle_design.kinematics import model_from_mjcf, model_from_mujoco, precheck_mjcf


def test_gravity_matches_mujoco_on_a_branching_tree_with_offsets(branching_arm_xml):
    m = mujoco.MjModel.from_xml_string(branching_arm_xml)
    d = mujoco.MjData(m)
    km = model_from_mujoco(m)
    rng = np.random.default_rng(0)
    for _ in range(20):
        q = rng.uniform(-np.pi, np.pi, m.nq)
        d.qpos[:] = q
        mujoco.mj_forward(m, d)
        g = pin.computeGeneralizedGravity(km.model, km.data, q)
        assert np.max(np.abs(g - d.qfrc_bias)) < 1e-12


def test_precheck_flags_every_dropped_construct():
    xml = """
<mujoco>
  <worldbody>
    <body name="a" gravcomp="1">
      <joint name="j1" axis="0 1 0" stiffness="2" springref="0.1"/>
      <geom size="0.1"/><site name="s1"/>
      <frame><body name="hidden"><geom size="0.1"/></body></frame>
    </body>
    <body name="second"><geom size="0.1"/><site name="s2"/></body>
  </worldbody>
  <tendon><spatial name="t" stiffness="5"><site site="s1"/><site site="s2"/></spatial></tendon>
  <equality><weld body1="a"/></equality>
  <actuator><motor joint="j1"/></actuator>
</mujoco>"""
    codes = [d.code for d in precheck_mjcf(xml)]
    assert codes == [
        "kinematics.joint_spring",
        "kinematics.tendon",
        "kinematics.equality",
        "kinematics.actuator",
        "kinematics.gravcomp",
        "kinematics.frame_body",
        "kinematics.extra_root",
    ]


def test_model_from_mjcf_refuses_gravcomp_but_accepts_springs(tmp_path):
    path = tmp_path / "a.xml"
    path.write_text(
        '<mujoco><worldbody><body name="a" gravcomp="1"><joint name="j" axis="0 1 0"/>'
        '<geom size="0.1"/></body></worldbody></mujoco>'
    )
    with pytest.raises(MjcfError) as err:
        model_from_mjcf(path)
    assert err.value.code == "kinematics.gravcomp"
    assert "gravcomp dropped (gravity compensation by fiat) (name 'a')" in err.value.message
    path.write_text(
        '<mujoco><worldbody><body name="a"><joint name="j" axis="0 1 0" stiffness="3"/>'
        '<geom size="0.1" pos="0.1 0 0"/></body></worldbody></mujoco>'
    )
    km = model_from_mjcf(path)
    assert [d.code for d in km.dropped] == ["kinematics.joint_spring"]
    assert km.joint_names == ["j"]


def test_ball_joint_is_refused_with_its_name():
    m = mujoco.MjModel.from_xml_string(
        '<mujoco><worldbody><body><joint name="shoulder" type="ball"/><geom size="0.1"/></body>'
        "</worldbody></mujoco>"
    )
    with pytest.raises(MjcfError) as err:
        model_from_mujoco(m)
    assert err.value.code == "kinematics.joint_type"
    assert (
        "joint 'shoulder' has type mjJNT_BALL; only hinge and slide joints are supported" in err.value.message
    )


def test_unnamed_joints_map_to_their_mujoco_ids():
    m = mujoco.MjModel.from_xml_string(
        '<mujoco><worldbody><body><joint axis="0 1 0"/><geom size="0.05" pos="0.2 0 0"/>'
        '<body pos="0.2 0 0"><joint axis="1 0 0"/><geom size="0.05" pos="0 0 -0.1"/></body></body>'
        "</worldbody></mujoco>"
    )
    km = model_from_mujoco(m)
    assert km.joint_names == ["joint0", "joint1"] and km.mj_joint_ids == [0, 1]
    d = mujoco.MjData(m)
    d.qpos[:] = [0.4, -0.7]
    mujoco.mj_forward(m, d)
    g = pin.computeGeneralizedGravity(km.model, km.data, d.qpos.copy())
    np.testing.assert_allclose(g, d.qfrc_bias, atol=1e-12)
