"""drop_visual_meshes: the same masses, inertias, collisions and dynamics, fewer mesh vertices."""

import mujoco
import numpy as np
import pytest

from rle_design.scene import arm_ids, drop_visual_meshes, load_robot

INERTIAL = ("body_mass", "body_inertia", "body_ipos", "body_iquat", "body_subtreemass")


@pytest.mark.parametrize("arm", arm_ids())
def test_dropping_visual_meshes_keeps_the_dynamics_bit_for_bit(arm):
    full = load_robot(arm, keyframes=False).compile()
    spec = load_robot(arm, keyframes=False)
    dropped = drop_visual_meshes(spec)
    lean = spec.compile()
    for name in INERTIAL:
        np.testing.assert_array_equal(getattr(lean, name), getattr(full, name), err_msg=name)
    # every colliding geom survives, in the same order (contacts are generated in geom order)
    collide = [
        full.geom(g).name for g in range(full.ngeom) if full.geom_contype[g] or full.geom_conaffinity[g]
    ]
    assert collide == [
        lean.geom(g).name for g in range(lean.ngeom) if lean.geom_contype[g] or lean.geom_conaffinity[g]
    ]
    assert lean.ngeom == full.ngeom - dropped
    if dropped:
        assert lean.nmeshvert < full.nmeshvert
    # M(q) and the bias forces C(q, v) + g(q) at random states: the same floats
    rng = np.random.default_rng(3)
    d_full, d_lean = mujoco.MjData(full), mujoco.MjData(lean)
    m_full, m_lean = np.zeros((full.nv, full.nv)), np.zeros((lean.nv, lean.nv))
    for _ in range(5):
        q, v = rng.uniform(-1.0, 1.0, full.nq), rng.standard_normal(full.nv)
        for m, d, mm in ((full, d_full, m_full), (lean, d_lean, m_lean)):
            d.qpos[:], d.qvel[:] = q, v
            mujoco.mj_forward(m, d)
            mujoco.mj_fullM(m, d, mm)
        np.testing.assert_array_equal(m_lean, m_full)
        np.testing.assert_array_equal(d_lean.qfrc_bias, d_full.qfrc_bias)


def test_a_body_without_its_own_inertia_keeps_its_visual_mesh():
    # A body whose inertia comes from its geoms: its visual mesh carries mass (here 2 of the 3 kg).
    xml = """<mujoco><asset><mesh name="m" vertex="0 0 0 1 0 0 0 1 0 0 0 1"/></asset><worldbody>
      <body name="a/link"><joint type="hinge"/>
        <geom type="box" size=".1 .1 .1" mass="1"/>
        <geom type="mesh" mesh="m" mass="2" contype="0" conaffinity="0"/></body>
      <body name="a/stated" pos="1 0 0"><joint type="hinge"/><inertial pos="0 0 0" mass="1" diaginertia=".1 .1 .1"/>
        <geom type="mesh" mesh="m" contype="0" conaffinity="0"/></body>
    </worldbody></mujoco>"""
    spec = mujoco.MjSpec.from_string(xml)
    assert drop_visual_meshes(spec, "a/") == 1  # only the stated-inertia body's mesh
    m = spec.compile()
    assert m.body("a/link").mass[0] == pytest.approx(3.0)
    assert m.nmesh == 1
