"""Closed-form mass properties: MuJoCo (geoms with density) and trimesh agree with the formulas."""

import mujoco
import numpy as np
import pytest
import trimesh

from rle_design.errors import MissingElement
from rle_design.mjcf.audit import audit_model
from rle_design.mjcf.loader import load_design
from rle_design.mjcf.mesh import compare_inertial, mesh_properties

A, B, C, RHO = 0.1, 0.2, 0.3, 1240.0  # box edges [m], PLA density [kg/m^3]
M = RHO * A * B * C  # m = rho a b c
I_BOX = (M * (B**2 + C**2) / 12, M * (A**2 + C**2) / 12, M * (A**2 + B**2) / 12)  # I_xx, I_yy, I_zz


def test_box_closed_form_in_mujoco(artifact):
    xml = f"""<mujoco><worldbody><body name="box"><freejoint/>
    <geom type="box" size="{A / 2} {B / 2} {C / 2}" density="{RHO}"/></body></worldbody></mujoco>"""
    model = load_design(artifact({"robot.xml": xml})).compile()
    box = audit_model(model).body("box")
    assert box.mass == pytest.approx(M, rel=1e-9, abs=1e-12)
    assert box.inertia == pytest.approx(I_BOX, rel=1e-6)
    assert box.inertia_valid and box.reason == ""


def test_box_closed_form_in_trimesh():
    props = mesh_properties(trimesh.creation.box(extents=[A, B, C]), RHO)
    assert props.watertight
    assert props.volume == pytest.approx(A * B * C, rel=1e-9)
    assert props.mass == pytest.approx(M, rel=1e-9)
    assert props.com == pytest.approx((0, 0, 0), abs=1e-12)
    assert np.diag(props.inertia) == pytest.approx(I_BOX, rel=1e-6)
    assert np.abs(np.asarray(props.inertia) - np.diag(np.diag(props.inertia))).max() < 1e-12
    assert props.bounds == (pytest.approx((-A / 2, -B / 2, -C / 2)), pytest.approx((A / 2, B / 2, C / 2)))


def test_compare_inertial_reports_both_numbers():
    props = mesh_properties(trimesh.creation.box(extents=[A, B, C]), RHO)
    assert compare_inertial(M, (0, 0, 0), I_BOX, props) == []
    findings = compare_inertial(2 * M, (0.05, 0, 0), np.diag(I_BOX) * 3, props, rtol=0.05, name="link1")
    assert [f.code for f in findings] == [
        "inertial.mass_mismatch",
        "inertial.com_mismatch",
        "inertial.inertia_mismatch",
    ]
    assert findings[0].message == "'link1': declared mass 14.88 kg != mesh mass 7.44 kg (rtol 0.05)"
    assert (
        findings[1].message
        == "'link1': declared COM [0.05, 0.0, 0.0] m != mesh COM [0.0, 0.0, 0.0] m (off by 0.05 m)"
    )


CHASSIS = """<mujoco>
  <worldbody>
    <body name="chassis" pos="0 0 0.1">
      <freejoint/>
      <geom name="deck" type="box" size="0.3 0.2 0.05" density="1000"/>
      <geom name="w1" type="sphere" size="0.05" pos="0.3 0.22 -0.05" density="1000"/>
      <geom name="w2" type="sphere" size="0.05" pos="0.3 -0.22 -0.05" density="1000"/>
      <geom name="w3" type="sphere" size="0.05" pos="-0.3 0.22 -0.05" density="1000"/>
      <geom name="w4" type="sphere" size="0.05" pos="-0.3 -0.22 -0.05" density="1000"/>
      <body name="mast" pos="0.2 0 0.05">
        <geom name="pole" type="cylinder" size="0.01 0.1" pos="0 0 0.1" mass="1" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
</mujoco>"""


def test_audit_com_bbox_and_footprint(artifact):
    audit = audit_model(load_design(artifact({"robot.xml": CHASSIS})).compile())
    m_deck = 1000 * 0.6 * 0.4 * 0.1  # 24 kg
    m_wheel = 1000 * 4 / 3 * np.pi * 0.05**3
    m_pole = 1.0
    total = m_deck + 4 * m_wheel + m_pole
    assert audit.total_mass == pytest.approx(total, rel=1e-9)
    # COM = sum m_i p_i / sum m_i (deck at z 0.1, wheels at z 0.05, pole centre at (0.2, 0, 0.25))
    com = np.array([m_pole * 0.2, 0.0, m_deck * 0.1 + 4 * m_wheel * 0.05 + m_pole * 0.25]) / total
    assert audit.com == pytest.approx(tuple(com), abs=1e-12)
    # bounding box: wheels reach x +-0.35, y +-0.27, z 0; pole top at 0.1 + 0.05 + 0.2 = 0.35
    assert audit.bbox_min == pytest.approx((-0.35, -0.27, 0.0), abs=1e-12)
    assert audit.bbox_max == pytest.approx((0.35, 0.27, 0.35), abs=1e-12)
    # footprint: the wheels (lowest contact geoms), not the deck
    assert audit.footprint_source == "contact"
    assert audit.footprint == pytest.approx((0.7, 0.54), abs=1e-12)
    assert audit.counts["nbody"] == 2 and audit.counts["ngeom"] == 6 and audit.counts["nu"] == 0


def test_footprint_falls_back_to_the_model_without_contact_geoms(artifact):
    xml = '<mujoco><worldbody><body><geom type="box" size=".1 .2 .3" contype="0" conaffinity="0"/></body></worldbody></mujoco>'
    audit = audit_model(load_design(artifact({"robot.xml": xml})).compile())
    assert audit.footprint_source == "model" and audit.footprint == pytest.approx((0.2, 0.4))


def test_mesh_geom_bbox_uses_vertices(artifact):
    # a tetrahedron's oriented AABB is loose; its vertices give the exact extent
    tet = trimesh.Trimesh(
        vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
        faces=[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    )
    xml = '<mujoco><asset><mesh name="t" file="t.stl"/></asset><worldbody><body pos="1 2 3" euler="0 0 90"><geom type="mesh" mesh="t"/></body></worldbody></mujoco>'
    audit = audit_model(
        load_design(artifact({"robot.xml": xml, "t.stl": tet.export(file_type="stl")})).compile()
    )
    # rotated 90 deg about z: x' = -y, y' = x
    assert audit.bbox_min == pytest.approx((0.0, 2.0, 3.0), abs=1e-6)
    assert audit.bbox_max == pytest.approx((1.0, 3.0, 4.0), abs=1e-6)


def test_invalid_inertia_is_reported(artifact):
    model = load_design(artifact({"robot.xml": CHASSIS})).compile()
    model.body_inertia[2] = [1.0, 1.0, 3.0]  # violates A + B >= C
    audit = audit_model(model)
    bad = audit.invalid_inertia
    assert [b.name for b in bad] == ["mast"]
    assert bad[0].reason == "triangle inequality violated: 1 + 1 < 3"
    model.body_inertia[2] = [0.0, 1.0, 1.0]
    assert audit_model(model).body("mast").reason == "non-positive principal moment in [0.0, 1.0, 1.0]"
    with pytest.raises(MissingElement) as info:
        audit.body("nope")
    assert str(info.value) == "body 'nope' does not exist. Available bodies: chassis, mast"


def test_audit_uses_qpos0(artifact):
    model = load_design(artifact({"robot.xml": CHASSIS})).compile()
    model.qpos0[2] = 1.0  # free joint z at the reference configuration
    assert audit_model(model).bbox_min[2] == pytest.approx(1.0 - 0.1, abs=1e-12)
    assert mujoco.MjData(model).qpos[2] == 1.0
