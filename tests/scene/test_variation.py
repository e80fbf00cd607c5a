"""Seeded variations: reproducible draws in declaration order, ranges, and spec/model edits that agree."""

import mujoco
import numpy as np
import pytest

from rle_design.errors import ConfigError
from rle_design.scene import (
    ComOffset,
    FrictionScale,
    MassScale,
    PointMass,
    Uniform,
    VariationSpace,
    element_id,
)

ARM = """<mujoco><worldbody>
  <geom name="floor" type="plane" size="2 2 0.1" friction="0.8 0.01 0.001"/>
  <body name="link1"><joint name="j1" axis="0 0 1"/>
    <inertial pos="0.05 0 0" mass="0.4" fullinertia="2e-4 3e-4 4e-4 1e-5 0 2e-5"/>
    <geom name="shell1" type="capsule" fromto="0 0 0 0.2 0 0" size="0.02" contype="0" conaffinity="0"/>
    <body name="link2" pos="0.2 0 0"><joint name="j2" axis="0 1 0"/>
      <inertial pos="0.08 0 0.01" quat="0.9 0.1 0.3 0.2" mass="0.3" diaginertia="1e-4 2e-4 2.5e-4"/>
      <geom name="wheel" type="sphere" size="0.03" pos="0.15 0 0"/>
      <site name="handle" pos="0.16 0.01 0.02"/>
    </body>
  </body>
</worldbody>
<contact><pair name="wheel_floor" geom1="wheel" geom2="floor" friction="0.9 0.7 0.005 0.0001 0.0001"/></contact>
</mujoco>"""

# Family 09's hidden device copy: link mass factors within +-15 %, then a handle payload of 10-40 g.
DEVICE = VariationSpace(
    (
        MassScale("link_scale", Uniform(1 - 0.15, 1 + 0.15, "1"), bodies=("link1", "link2")),
        PointMass("payload", Uniform(0.01, 0.04, "kg"), site="handle"),
    )
)
# Family 08's scene variation: one friction factor, then a 3-axis payload COM offset of +-1 cm.
SCENE = VariationSpace(
    (
        FrictionScale("friction", Uniform(0.85, 1.15, "1"), pairs=("wheel_floor",), axis=1),
        ComOffset("payload_com", Uniform(-0.01, 0.01, "m"), body="link2"),
    )
)


def test_sample_is_reproducible_from_the_seed():
    a, b = DEVICE.sample(np.random.default_rng(7)), DEVICE.sample(np.random.default_rng(7))
    assert a == b
    assert DEVICE.sample(np.random.default_rng(8)).values != a.values


def test_terms_draw_in_declaration_order_with_one_uniform_call_each():
    rng = np.random.default_rng(2024)
    expected_scale = tuple(rng.uniform(0.85, 1.15, 2))
    expected_payload = rng.uniform(0.01, 0.04)
    var = DEVICE.sample(np.random.default_rng(2024))
    assert var["link_scale"] == expected_scale and var["payload"] == (expected_payload,)
    rng = np.random.default_rng(5)
    expected = (rng.uniform(0.85, 1.15), tuple(rng.uniform(-0.01, 0.01, 3)))
    var = SCENE.sample(np.random.default_rng(5))
    assert (var["friction"][0], var["payload_com"]) == expected


def test_draws_cover_their_declared_ranges():
    rng = np.random.default_rng(0)
    draws = [SCENE.sample(rng) for _ in range(500)]
    friction = np.array([d["friction"][0] for d in draws])
    com = np.array([d["payload_com"] for d in draws])
    assert 0.85 <= friction.min() < 0.86 and 1.14 < friction.max() <= 1.15
    assert -0.01 <= com.min() < -0.0098 and 0.0098 < com.max() <= 0.01
    assert abs(com.mean()) < 1e-3  # centred


def test_nominal_variation_changes_nothing():
    m = mujoco.MjModel.from_xml_string(ARM)
    for space in (DEVICE, SCENE):
        out = space.nominal().apply(m)
        for field in (
            "body_mass",
            "body_inertia",
            "body_ipos",
            "body_iquat",
            "geom_friction",
            "pair_friction",
        ):
            np.testing.assert_array_equal(getattr(out, field), getattr(m, field), err_msg=field)


def test_spec_and_model_edits_agree():
    var = SCENE.sample(np.random.default_rng(3))
    scale = VariationSpace(
        (MassScale("mass", Uniform(0.5, 2.0, "1"), bodies=("link1", "link2"), per_body=False),)
    )
    mvar = scale.sample(np.random.default_rng(3))
    spec = mujoco.MjSpec.from_string(ARM)
    var.edit_spec(spec)
    mvar.edit_spec(spec)
    from_spec = spec.compile()
    from_model = mvar.apply(var.apply(mujoco.MjModel.from_xml_string(ARM)))
    for field in ("body_mass", "body_inertia", "body_ipos", "pair_friction", "geom_friction"):
        np.testing.assert_allclose(
            getattr(from_spec, field), getattr(from_model, field), rtol=1e-12, err_msg=field
        )
    pair = element_id(from_spec, "pair", "wheel_floor")
    assert from_spec.pair_friction[pair, 1] == pytest.approx(0.7 * var["friction"][0], rel=1e-15)
    assert from_spec.pair_friction[pair, 0] == 0.9  # other coefficients untouched


def test_point_mass_obeys_the_parallel_axis_theorem():
    m = mujoco.MjModel.from_xml_string(ARM)
    mp = 0.025
    space = VariationSpace((PointMass("payload", Uniform(mp, mp, "kg"), site="handle"),))
    out = space.sample(np.random.default_rng(0)).apply(m)
    b, s = element_id(m, "body", "link2"), element_id(m, "site", "handle")
    m0, c0, p = m.body_mass[b], m.body_ipos[b], m.site_pos[s]
    c = (m0 * c0 + mp * p) / (m0 + mp)
    assert out.body_mass[b] == pytest.approx(m0 + mp, rel=1e-15)
    np.testing.assert_allclose(out.body_ipos[b], c, atol=1e-15)

    def tensor(model):  # inertia about the body's COM, in the body frame
        r = np.zeros(9)
        mujoco.mju_quat2Mat(r, model.body_iquat[b])
        r = r.reshape(3, 3)
        return r @ np.diag(model.body_inertia[b]) @ r.T

    def shift(mass, d):
        return mass * (d @ d * np.eye(3) - np.outer(d, d))

    expected = tensor(m) + shift(m0, c0 - c) + shift(mp, p - c)
    np.testing.assert_allclose(tensor(out), expected, atol=1e-15)
    # the same payload as a welded child body (spec edit) gives the same mass matrix at any pose
    spec = mujoco.MjSpec.from_string(ARM)
    space.nominal().edit_spec(spec)  # a zero mass adds nothing
    assert spec.compile().nbody == m.nbody
    space.sample(np.random.default_rng(0)).edit_spec(spec)
    welded = spec.compile()
    assert welded.nbody == m.nbody + 1

    def mass_matrix(model, q):
        d = mujoco.MjData(model)
        d.qpos[:] = q
        mujoco.mj_forward(model, d)
        mat = np.zeros((model.nv, model.nv))
        mujoco.mj_fullM(model, d, mat)
        return mat

    for q in np.random.default_rng(1).uniform(-2.0, 2.0, (5, 2)):
        np.testing.assert_allclose(mass_matrix(out, q), mass_matrix(welded, q), atol=1e-8)


def test_select_keeps_the_draw_of_the_chosen_terms():
    var = SCENE.sample(np.random.default_rng(11))
    friction_only = var.select("friction")
    assert friction_only.names == ["friction"] and friction_only["friction"] == var["friction"]
    spec = mujoco.MjSpec.from_string(ARM.replace('name="link2"', 'name="arm2"'))  # no body for payload_com
    friction_only.edit_spec(spec)
    m = spec.compile()
    assert m.pair_friction[0, 1] == pytest.approx(0.7 * var["friction"][0], rel=1e-15)
    with pytest.raises(KeyError, match="variation term 'mu' does not exist"):
        var.select("mu")


def test_lookup_by_name_lists_the_terms():
    var = SCENE.nominal()
    assert var["friction"] == (1.0,) and var["payload_com"] == (0.0, 0.0, 0.0)
    with pytest.raises(
        KeyError, match="variation term 'mass' does not exist. Available: friction, payload_com"
    ):
        var["mass"]


@pytest.mark.parametrize(
    "term, message",
    [
        (FrictionScale("mu", Uniform(0.9, 1.1, "1")), "FrictionScale 'mu' names no geom and no pair"),
        (
            FrictionScale("mu", Uniform(0.0, 1.1, "1"), geoms=("floor",)),
            "FrictionScale 'mu': factors must be > 0, got low 0.0",
        ),
        (
            FrictionScale("mu", Uniform(0.9, 1.1, "1"), geoms=("floor",), axis=3),
            "FrictionScale 'mu': axis 3 out of range",
        ),
        (MassScale("m", Uniform(0.9, 1.1, "1"), bodies=()), "MassScale 'm' names no body"),
        (
            MassScale("m", Uniform(1.2, 1.1, "1"), bodies=("a",)),
            "MassScale 'm': range must be finite with low <= high, got [1.2, 1.1]",
        ),
        (
            PointMass("p", Uniform(-0.1, 0.1, "kg"), site="s"),
            "PointMass 'p': masses must be >= 0, got low -0.1",
        ),
        (ComOffset("", Uniform(-0.1, 0.1, "m"), body="b"), "ComOffset.name must not be empty"),
    ],
)
def test_invalid_terms_are_refused_with_exact_messages(term, message):
    with pytest.raises(ConfigError) as err:
        VariationSpace((term,)).sample(np.random.default_rng(0))
    assert str(err.value) == message


def test_repeated_names_and_implicit_inertia_are_refused():
    twice = VariationSpace((ComOffset("c", Uniform(0, 0, "m"), body="link1"),) * 2)
    with pytest.raises(ConfigError, match="term names must be unique, repeated: c"):
        twice.nominal()
    spec = mujoco.MjSpec.from_string(
        ARM.replace('<inertial pos="0.05 0 0" mass="0.4" fullinertia="2e-4 3e-4 4e-4 1e-5 0 2e-5"/>', "")
    )
    space = VariationSpace((MassScale("m", Uniform(0.9, 1.1, "1"), bodies=("link1",)),))
    with pytest.raises(ConfigError) as err:
        space.nominal().edit_spec(spec)
    assert str(err.value) == (
        "MassScale 'm': body 'link1' has no explicit <inertial>; scale it on the compiled model with Variation.apply"
    )
