"""Attachment at a site with name prefixes (dm_control.mjcf style), checked on the compiled model."""

import mujoco
import numpy as np
import pytest

from rle_design.errors import ConfigError, MissingElement, MjcfError
from rle_design.scene import attach, element_id, has_element

PARENT = """<mujoco><worldbody>
  <body name="base" pos="0 0 0.5"><geom type="box" size="0.2 0.2 0.05" mass="10"/>
    <site name="left" pos="0 0.1 0.05" euler="0 0 90"/>
    <site name="right" pos="0 -0.1 0.05"/>
  </body>
</worldbody></mujoco>"""

CHILD = """<mujoco><worldbody>
  <body name="link" pos="0 0 0"><joint name="hinge" axis="0 0 1"/><geom type="capsule" size="0.02 0.1" mass="0.5"/>
    <site name="tip" pos="0 0 0.2"/>
  </body>
</worldbody>
<actuator><motor name="drive" joint="hinge"/></actuator>
<sensor><jointpos name="angle" joint="hinge"/></sensor>
</mujoco>"""


def _two_copies() -> mujoco.MjModel:
    spec = mujoco.MjSpec.from_string(PARENT)
    attach(spec, mujoco.MjSpec.from_string(CHILD), "left", "l/")
    attach(spec, mujoco.MjSpec.from_string(CHILD), "right", "r/")
    return spec.compile()


def test_two_copies_get_their_prefixes_and_keep_everything():
    m = _two_copies()
    for p in ("l/", "r/"):
        for kind, name in [("body", "link"), ("joint", "hinge"), ("site", "tip"), ("actuator", "drive")]:
            element_id(m, kind, p + name)
        element_id(m, "sensor", p + "angle")
    assert (m.nbody, m.njnt, m.nu, m.nsensor) == (4, 2, 2, 2)
    # actuators still drive their own copy's joint
    for p in ("l/", "r/"):
        assert m.actuator_trnid[element_id(m, "actuator", p + "drive"), 0] == element_id(
            m, "joint", p + "hinge"
        )
    assert m.body_subtreemass[0] == pytest.approx(10.0 + 2 * 0.5, abs=1e-12)


def test_attached_root_frame_is_the_site_frame():
    m = _two_copies()
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    for p, site in (("l/", "left"), ("r/", "right")):
        b, s = element_id(m, "body", p + "link"), element_id(m, "site", site)
        np.testing.assert_allclose(d.xpos[b], d.site_xpos[s], atol=1e-12)
        np.testing.assert_allclose(d.xmat[b], d.site_xmat[s], atol=1e-12)
    # the left site is turned 90 deg about z: the child's tip (0 0 0.2) stays above the site
    tip = d.site_xpos[element_id(m, "site", "l/tip")]
    np.testing.assert_allclose(tip, [0.0, 0.1, 0.5 + 0.05 + 0.2], atol=1e-12)


def test_attach_a_named_body_of_a_spec_with_several_roots():
    child = mujoco.MjSpec.from_string(
        CHILD.replace("</worldbody>", '<body name="other"><geom size="0.1"/></body></worldbody>')
    )
    spec = mujoco.MjSpec.from_string(PARENT)
    with pytest.raises(MjcfError) as err:
        attach(spec, child, "left", "c/")
    assert (
        str(err.value)
        == "cannot choose the body to attach: the child has 2 root bodies (link, other); name one"
    )
    attach(spec, child, "left", "c/", body="other")
    m = spec.compile()
    assert element_id(m, "body", "c/other") > 0 and not has_element(m, "body", "c/link")


def test_attach_errors_name_the_site_and_the_prefix():
    spec = mujoco.MjSpec.from_string(PARENT)
    with pytest.raises(MissingElement) as err:
        attach(spec, mujoco.MjSpec.from_string(CHILD), "middle", "m/")
    assert str(err.value) == "site 'middle' does not exist. Available sites: left, right"
    with pytest.raises(ConfigError) as err:
        attach(spec, mujoco.MjSpec.from_string(CHILD), "left", "")
    assert str(err.value) == "attach: prefix must not be empty (it keeps attached names unique)"


def test_a_prefix_used_twice_is_refused_with_mujocos_reason():
    spec = mujoco.MjSpec.from_string(PARENT)
    attach(spec, mujoco.MjSpec.from_string(CHILD), "left", "l/")
    with pytest.raises(MjcfError) as err:
        attach(spec, mujoco.MjSpec.from_string(CHILD), "right", "l/")
    assert str(err.value).startswith("cannot attach 'link' with prefix 'l/': Error: repeated name 'l/")
    assert err.value.code == "scene.attach"
