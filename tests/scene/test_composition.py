"""Composition: a catalog arm at a site the caller names, a payload at its tool, in an arena."""

import mujoco
import numpy as np
import pytest

from rle_design.catalog import load_catalog
from rle_design.errors import ConfigError
from rle_design.scene import Arena, PhysicsOptions, compile_spec, compose, element_id

DECK = """<mujoco><option timestep="0.005"/><worldbody><body name="cart" pos="0 0 0.3"><freejoint/>
<geom type="box" size=".3 .2 .1" mass="20"/><site name="deck" pos="0.1 0 0.1" euler="0 0 90"/></body>
</worldbody></mujoco>"""


def test_arm_sits_on_the_named_site_and_holds_the_payload():
    spec = compose(mujoco.MjSpec.from_string(DECK), "panda", "payload_1kg", mount_site="deck")
    m = compile_spec(spec)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    root, site = element_id(m, "body", "panda/base"), element_id(m, "site", "deck")
    np.testing.assert_allclose(d.xpos[root], d.site_xpos[site], atol=1e-12)
    np.testing.assert_allclose(d.xmat[root], d.site_xmat[site], atol=1e-12)
    payload = element_id(m, "body", "payload/payload")
    tool = element_id(m, "site", "panda/tool_site")
    np.testing.assert_allclose(d.xpos[payload], d.site_xpos[tool], atol=1e-12)
    assert m.body_subtreemass[0] == pytest.approx(
        20.0 + load_catalog("arms").get("panda").mass + 1.0, abs=1e-3
    )
    assert m.opt.timestep == 0.002 and element_id(m, "geom", "floor") >= 0  # the arena's options and floor


def test_an_arm_needs_a_mount_site():
    with pytest.raises(ConfigError) as err:
        compose(mujoco.MjSpec.from_string(DECK), "ur5e")
    assert str(err.value) == "compose: an arm needs mount_site, the design's site that carries it"


def test_without_arena_the_design_keeps_its_options():
    m = compile_spec(compose(mujoco.MjSpec.from_string(DECK), "panda", mount_site="deck", arena=None))
    assert m.opt.timestep == 0.005 and m.ngeom > 1 and m.nlight == 0
    custom = Arena(physics=PhysicsOptions(timestep=0.001))
    m = compile_spec(compose(mujoco.MjSpec.from_string(DECK), "xarm7", mount_site="deck", arena=custom))
    # xarm7 brings integrator=implicitfast in its <option>; the arena's options win
    assert m.opt.timestep == 0.001 and m.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
