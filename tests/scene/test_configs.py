"""Spec-edit configs: validate() refuses bad fields with exact messages, edit_spec() sets compiled fields."""

import mujoco
import numpy as np
import pytest

from rle_design.errors import ConfigError, MissingElement
from rle_design.scene import (
    Arena,
    CameraConfig,
    FloorConfig,
    HeadlightConfig,
    LightConfig,
    PhysicsOptions,
    SiteConfig,
    SkyboxConfig,
    element_id,
)

BOX = """<mujoco><worldbody><body name="box" pos="0 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1"/>
</body></worldbody></mujoco>"""


def _refused(config, message: str) -> None:
    with pytest.raises(ConfigError) as err:
        config.validate()
    assert str(err.value) == message
    assert err.value.code == "config.invalid"
    with pytest.raises(ConfigError):  # edit_spec validates first and leaves the spec alone
        config.edit_spec(mujoco.MjSpec.from_string(BOX))


@pytest.mark.parametrize(
    "config, message",
    [
        (PhysicsOptions(timestep=0.0), "PhysicsOptions.timestep must be > 0, got 0.0"),
        (
            PhysicsOptions(integrator=7),
            "PhysicsOptions.integrator must be an mjtIntegrator value, got 7. "
            "Available: 0 (mjINT_EULER), 1 (mjINT_RK4), 2 (mjINT_IMPLICIT), 3 (mjINT_IMPLICITFAST), 4 (mjINT_DISCRETE)",
        ),
        (
            PhysicsOptions(cone=3),
            "PhysicsOptions.cone must be an mjtCone value, got 3. Available: 0 (mjCONE_PYRAMIDAL), 1 (mjCONE_ELLIPTIC)",
        ),
        (PhysicsOptions(noslip_iterations=-1), "PhysicsOptions.noslip_iterations must be >= 0, got -1"),
        (PhysicsOptions(gravity=(0.0, -9.81)), "PhysicsOptions.gravity must have 3 entries, got 2"),
        (PhysicsOptions(gravity=(0.0, 0.0, float("nan"))), "PhysicsOptions.gravity must be finite, got nan"),
        (FloorConfig(name=""), "FloorConfig.name must not be empty"),
        (FloorConfig(half_size=-1.0), "FloorConfig.half_size must be > 0, got -1.0"),
        (FloorConfig(friction=(-1.0, 0.0, 0.0)), "FloorConfig.friction must be >= 0, got (-1.0, 0.0, 0.0)"),
        (
            FloorConfig(rgba=(1.0, 1.0, 1.0, 2.0)),
            "FloorConfig.rgba channels must be in [0, 1], got (1.0, 1.0, 1.0, 2.0)",
        ),
        (SkyboxConfig(resolution=0), "SkyboxConfig.resolution must be >= 1, got 0"),
        (
            SkyboxConfig(top=(0.5, 0.5, 1.5)),
            "SkyboxConfig.top channels must be in [0, 1], got (0.5, 0.5, 1.5)",
        ),
        (LightConfig(dir=(0.0, 0.0, 0.0)), "LightConfig.dir must not be the zero vector"),
        (HeadlightConfig(ambient=(0.1, 0.1)), "HeadlightConfig.ambient must have 3 entries, got 2"),
        (CameraConfig(name=""), "CameraConfig.name must not be empty"),
        (CameraConfig(name="c", fovy_deg=180.0), "CameraConfig.fovy_deg must be in (0, 180), got 180.0"),
        (
            CameraConfig(name="c", pos=(1.0, 0.0, 0.0), look_at=(1.0, 0.0, 0.0)),
            "CameraConfig.look_at must differ from pos, both are (1.0, 0.0, 0.0)",
        ),
        (
            CameraConfig(name="c", quat=(0.0, 0.0, 0.0, 0.0)),
            "CameraConfig.quat must not be the zero quaternion",
        ),
        (SiteConfig(name=""), "SiteConfig.name must not be empty"),
        (SiteConfig(name="s", radius=0.0), "SiteConfig.radius must be > 0, got 0.0"),
        (SiteConfig(name="s", group=6), "SiteConfig.group must be in 0..5, got 6"),
        (SiteConfig(name="s", pos=(0.0, 0.0)), "SiteConfig.pos must have 3 entries, got 2"),
        (Arena(floor=FloorConfig(grid=0.0)), "FloorConfig.grid must be > 0, got 0.0"),
    ],
)
def test_validate_refuses_with_exact_messages(config, message):
    _refused(config, message)


def test_physics_options_reach_the_compiled_model():
    spec = mujoco.MjSpec.from_string(BOX)
    PhysicsOptions(
        timestep=0.001, integrator=1, cone=0, noslip_iterations=3, gravity=(0.0, 0.0, -1.62)
    ).edit_spec(spec)
    m = spec.compile()
    assert m.opt.timestep == 0.001 and m.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4
    assert m.opt.cone == mujoco.mjtCone.mjCONE_PYRAMIDAL and m.opt.noslip_iterations == 3
    np.testing.assert_array_equal(m.opt.gravity, [0.0, 0.0, -1.62])


def test_arena_adds_floor_sky_light_and_options():
    spec = mujoco.MjSpec.from_string(BOX)
    Arena(floor=FloorConfig(friction=(0.7, 0.01, 0.001), half_size=5.0)).edit_spec(spec)
    m = spec.compile()
    floor = element_id(m, "geom", "floor")
    assert m.geom_type[floor] == mujoco.mjtGeom.mjGEOM_PLANE and m.geom_bodyid[floor] == 0
    np.testing.assert_allclose(m.geom_friction[floor], [0.7, 0.01, 0.001])
    np.testing.assert_allclose(m.geom_size[floor], [5.0, 5.0, 0.05])
    assert m.tex_type[element_id(m, "texture", "sky")] == mujoco.mjtTexture.mjTEXTURE_SKYBOX
    assert m.light_type[element_id(m, "light", "key")] == mujoco.mjtLightType.mjLIGHT_DIRECTIONAL
    np.testing.assert_allclose(m.vis.headlight.ambient, [0.35, 0.35, 0.35])
    assert (
        m.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
        and m.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC
    )
    # the box rests on the floor: 1 s of simulation, no warning, settled at z = 0.1
    d = mujoco.MjData(m)
    mujoco.mj_step(m, d, 500)
    assert abs(d.qpos[2] - 0.1) < 2e-3 and all(w.number == 0 for w in d.warning)


def test_arena_keeps_a_floor_and_lights_the_design_brings():
    xml = BOX.replace(
        "<worldbody>",
        '<worldbody><light name="lamp" pos="0 0 3"/><geom name="floor" type="plane" size="1 1 0.1" friction="0.3"/>',
    )
    spec = mujoco.MjSpec.from_string(xml)
    Arena().edit_spec(spec)
    m = spec.compile()
    assert m.ngeom == 2 and m.nlight == 1
    assert m.geom_friction[element_id(m, "geom", "floor"), 0] == pytest.approx(0.3)


def test_bare_arena_only_sets_physics():
    spec = mujoco.MjSpec.from_string(BOX)
    Arena.bare(PhysicsOptions(timestep=0.004)).edit_spec(spec)
    m = spec.compile()
    assert (m.ngeom, m.nlight, m.ntex, m.opt.timestep) == (1, 0, 0, 0.004)


def test_camera_aimed_at_a_point_looks_at_it():
    spec = mujoco.MjSpec.from_string(BOX)
    pos, target = np.array([2.0, -1.0, 1.5]), np.array([0.0, 0.0, 0.1])
    CameraConfig(name="overview", pos=tuple(pos), look_at=tuple(target), fovy_deg=60.0).edit_spec(spec)
    m = spec.compile()
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    c = element_id(m, "camera", "overview")
    rot = d.cam_xmat[c].reshape(3, 3)
    np.testing.assert_allclose(-rot[:, 2], (target - pos) / np.linalg.norm(target - pos), atol=1e-12)
    assert abs(rot[2, 0]) < 1e-12 and rot[2, 1] > 0  # no roll: the image x axis is level, y points up
    assert m.cam_fovy[c] == 60.0


def test_camera_and_site_errors_name_the_element():
    spec = mujoco.MjSpec.from_string(BOX)
    CameraConfig(name="overview").edit_spec(spec)
    with pytest.raises(ConfigError, match="camera 'overview' already exists"):
        CameraConfig(name="overview").edit_spec(spec)
    with pytest.raises(MissingElement) as err:
        SiteConfig(name="s", body="lid").edit_spec(spec)
    assert str(err.value) == "body 'lid' does not exist. Available bodies: box, world"


def test_site_on_a_body():
    spec = mujoco.MjSpec.from_string(BOX)
    SiteConfig(name="corner", body="box", pos=(0.1, 0.1, 0.1), radius=0.01, group=3).edit_spec(spec)
    m = spec.compile()
    s = element_id(m, "site", "corner")
    assert m.site_bodyid[s] == element_id(m, "body", "box") and m.site_group[s] == 3
    np.testing.assert_allclose(m.site_pos[s], [0.1, 0.1, 0.1])
    assert m.site_size[s, 0] == 0.01
