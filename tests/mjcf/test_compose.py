"""Composition of a design with a catalog arm and payload (``rle_design.scene.compose``)."""

import mujoco
import numpy as np
import pytest

from rle_design.catalog import load_catalog
from rle_design.errors import ConfigError, MissingElement, MjcfError
from rle_design.scene import arm_ids, compile_spec, compose, element_id

BASE = """<mujoco><worldbody><body name="base" pos="0 0 0.2"><freejoint/>
<geom type="box" size=".25 .2 .1" mass="38"/><site name="arm_mount_site" pos="0 0 0.1"/></body></worldbody></mujoco>"""

SITE = "arm_mount_site"


def test_arm_ids_come_from_the_catalog():
    assert arm_ids() == tuple(load_catalog("arms").ids)


@pytest.mark.parametrize("arm", arm_ids())
def test_attach_arm_and_payload_adds_catalog_masses(arm):
    spec = mujoco.MjSpec.from_string(BASE)
    compose(spec, arm, "payload_2kg", mount_site=SITE)
    model = compile_spec(spec)
    arm_cat = load_catalog("arms").get(arm)
    # total mass = base 38 kg + arm model mass + 2 kg payload
    assert model.body_subtreemass[0] == pytest.approx(38.0 + arm_cat.mass + 2.0, abs=1e-3)
    assert model.nu == arm_cat.dof and model.nq == 7 + arm_cat.dof
    assert model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC
    assert model.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    assert model.nkey == 0  # the composition adds no keyframe
    element_id(model, "site", f"{arm}/tool_site")


def test_arm_sits_on_mount_site():
    spec = mujoco.MjSpec.from_string(BASE)
    compose(spec, "ur5e", mount_site=SITE)
    model = compile_spec(spec)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    root = element_id(model, "body", "ur5e/base")
    site = element_id(model, "site", "arm_mount_site")
    np.testing.assert_allclose(data.xpos[root], data.site_xpos[site], atol=1e-12)


def test_mount_site_is_a_parameter():
    spec = mujoco.MjSpec.from_string(BASE.replace("arm_mount_site", "top"))
    compose(spec, "panda", mount_site="top")
    element_id(compile_spec(spec), "body", "panda/base")


def test_missing_mount_site_lists_sites():
    spec = mujoco.MjSpec.from_string(BASE.replace("arm_mount_site", "mount"))
    with pytest.raises(MissingElement) as err:
        compose(spec, "panda", mount_site=SITE)
    assert str(err.value) == "site 'arm_mount_site' does not exist. Available sites: mount"
    assert err.value.code == "contract.missing_site"


def test_an_arm_needs_a_mount_site():
    with pytest.raises(ConfigError, match="mount_site"):
        compose(mujoco.MjSpec.from_string(BASE), "panda")


def test_payload_without_arm():
    with pytest.raises(MjcfError, match="a payload needs an arm"):
        compose(mujoco.MjSpec.from_string(BASE), None, "payload_1kg")


def test_unknown_arm():
    with pytest.raises(MjcfError, match="unknown arm 'kuka'. Available arms: panda, ur5e, xarm7"):
        compose(mujoco.MjSpec.from_string(BASE), "kuka", mount_site=SITE)


def test_composed_scene_steps_one_second_without_warnings():
    spec = mujoco.MjSpec.from_string(BASE)
    compose(spec, "xarm7", "payload_1kg", mount_site=SITE)
    model = compile_spec(spec)
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data, int(1.0 / model.opt.timestep))
    assert np.isfinite(data.qpos).all()
    assert all(w.number == 0 for w in data.warning)
