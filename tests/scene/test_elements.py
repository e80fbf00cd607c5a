"""Named-element lookup: ids by name, and MissingElement listing the alternatives."""

import mujoco
import pytest

from rle_design.errors import ConfigError, MissingElement
from rle_design.scene import element_id, element_ids, element_names, find_body, find_site, has_element

XML = """<mujoco>
  <worldbody>
    <body name="upper"><joint name="shoulder"/><geom size="0.05"/><site name="elbow_site"/>
      <body name="lower" pos="0 0 -0.3"><joint name="elbow"/><geom size="0.05"/><site name="tool"/></body>
    </body>
    <camera name="overview" pos="1 0 1"/>
  </worldbody>
  <actuator><motor name="m_shoulder" joint="shoulder"/><motor name="m_elbow" joint="elbow"/></actuator>
  <sensor><jointpos name="q_elbow" joint="elbow"/></sensor>
  <keyframe><key name="home" qpos="0 0"/><key name="bent" qpos="0 1"/></keyframe>
</mujoco>"""


@pytest.fixture(scope="module")
def model():
    return mujoco.MjModel.from_xml_string(XML)


def test_ids_match_mujoco_for_every_kind(model):
    for kind, obj, name in [
        ("body", mujoco.mjtObj.mjOBJ_BODY, "lower"),
        ("joint", mujoco.mjtObj.mjOBJ_JOINT, "elbow"),
        ("site", mujoco.mjtObj.mjOBJ_SITE, "tool"),
        ("actuator", mujoco.mjtObj.mjOBJ_ACTUATOR, "m_elbow"),
        ("sensor", mujoco.mjtObj.mjOBJ_SENSOR, "q_elbow"),
        ("camera", mujoco.mjtObj.mjOBJ_CAMERA, "overview"),
        ("keyframe", mujoco.mjtObj.mjOBJ_KEY, "bent"),
    ]:
        expected = mujoco.mj_name2id(model, obj, name)
        assert expected >= 0
        assert element_id(model, kind, name) == expected
        assert element_id(model, obj, name) == expected  # an mjtObj works as the kind


def test_missing_site_lists_the_sites(model):
    with pytest.raises(MissingElement) as err:
        element_id(model, "site", "tool_site")
    assert str(err.value) == "site 'tool_site' does not exist. Available sites: elbow_site, tool"
    assert err.value.code == "contract.missing_element"
    assert err.value.available == ["elbow_site", "tool"]


def test_missing_keyframe_and_actuator_messages(model):
    with pytest.raises(MissingElement) as err:
        element_id(model, mujoco.mjtObj.mjOBJ_KEY, "stowed")
    assert str(err.value) == "keyframe 'stowed' does not exist. Available keyframes: bent, home"
    with pytest.raises(MissingElement) as err:
        element_id(model, "actuator", "m_wrist", code="contract.missing_actuator")
    assert str(err.value) == "actuator 'm_wrist' does not exist. Available actuators: m_elbow, m_shoulder"
    assert err.value.code == "contract.missing_actuator"


def test_a_kind_without_elements_says_none(model):
    with pytest.raises(MissingElement) as err:
        element_id(model, "tendon", "cable")
    assert str(err.value) == "tendon 'cable' does not exist. Available tendons: (none)"


def test_unknown_kind_lists_the_kinds(model):
    with pytest.raises(ConfigError) as err:
        element_id(model, "link", "upper")
    assert str(err.value).startswith(
        "element kind 'link' does not exist. Available kinds: body, joint, geom, site"
    )
    assert err.value.code == "scene.unknown_kind"


def test_element_ids_keep_the_order_and_has_element(model):
    assert element_ids(model, "joint", ["elbow", "shoulder"]) == [1, 0]
    assert has_element(model, "sensor", "q_elbow") and not has_element(model, "sensor", "q_wrist")
    assert element_names(model, "body") == ["world", "upper", "lower"]


def test_spec_lookups_list_the_alternatives():
    spec = mujoco.MjSpec.from_string(XML)
    assert find_site(spec, "tool").name == "tool"
    assert find_body(spec, "world") is not None
    with pytest.raises(MissingElement) as err:
        find_site(spec, "mount")
    assert str(err.value) == "site 'mount' does not exist. Available sites: elbow_site, tool"
    assert err.value.code == "contract.missing_site"


@pytest.mark.parametrize(
    ("kind", "plural"),
    [("body", "bodies"), ("mesh", "meshes"), ("site", "sites"), ("key", "keys"), ("actuator", "actuators")],
)
def test_missing_element_names_the_kind_in_the_plural(kind, plural):
    err = MissingElement(kind, "x", ["a"])
    assert str(err) == f"{kind} 'x' does not exist. Available {plural}: a"
