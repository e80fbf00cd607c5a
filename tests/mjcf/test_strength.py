"""Strength of added parts against closed-form cantilevers: sigma = M c / I (+ N / A), delta = F L^3 / 3 E I."""

import mujoco
import numpy as np
import pytest

from rle_design.catalog import load_catalog
from rle_design.mjcf.sections import beam_section, polygon_section
from rle_design.mjcf.strength import G, part_loads, spring_tensions, strength_faults

PLA = load_catalog("materials").get("pla")
R, L, M_TIP = 0.004, 0.08, 0.2  # rod radius, length [m]; steel weight at its tip [kg]
DYN, SF = 2.0, 2.0


def _rod_model(radius: float = R, length: float = L, tip: float = M_TIP) -> mujoco.MjModel:
    """A fixed support block, and a horizontal rod from its face with a sphere at the far end."""
    return mujoco.MjModel.from_xml_string(
        f"""<mujoco><worldbody>
        <body name="support"><geom name="block" type="box" size="0.02 0.02 0.02" pos="-0.02 0 0"/></body>
        <body name="arm">
          <geom name="rod" type="cylinder" fromto="0 0 0 {length} 0 0" size="{radius}"/>
          <geom name="weight" type="sphere" pos="{length} 0 0" size="0.008"/>
        </body></worldbody></mujoco>"""
    )


def _loads(m: mujoco.MjModel, masses: np.ndarray, tensions=None):
    return part_loads(
        m,
        [2],
        masses=masses,
        material_of=lambda g: PLA,
        tensions=tensions,
        dynamic_factor=DYN,
        safety_factor=lambda mat: SF,
        deflection_ratio=0.02,
        join_tol=1e-3,
    )


def test_round_and_rectangular_sections():
    rod = beam_section(int(mujoco.mjtGeom.mjGEOM_CYLINDER), np.array([R, L / 2, 0]))
    assert rod.inertia == pytest.approx(np.pi * R**4 / 4)  # I = pi r^4 / 4
    assert rod.bending == pytest.approx(R / (np.pi * R**4 / 4))  # c / I
    assert rod.area == pytest.approx(np.pi * R**2) and rod.length == pytest.approx(L)
    b, h = 0.003, 0.0004  # the 0.4 mm x 3 mm strut, 12 cm long
    strut = beam_section(int(mujoco.mjtGeom.mjGEOM_BOX), np.array([b / 2, 0.06, h / 2]))
    assert strut.length == pytest.approx(0.12) and np.allclose(strut.axis, [0, 1, 0])
    assert strut.inertia == pytest.approx(b * h**3 / 12)  # the weak axis
    # worst-direction bending of a rectangle: sqrt((c_y / I_y)^2 + (c_z / I_z)^2)
    assert strut.bending == pytest.approx(np.hypot((h / 2) / (b * h**3 / 12), (b / 2) / (h * b**3 / 12)))


def test_cantilever_rod_with_a_tip_load_closed_form():
    m = _rod_model()
    masses = np.array([0.0, 0.0, M_TIP])  # a weightless rod: only the tip load
    (load,) = _loads(m, masses)
    f = M_TIP * G
    i = np.pi * R**4 / 4
    moment = DYN * f * L  # M = F L at the clamp (dynamic factor on the weight)
    sigma = moment * R / i + DYN * f / (np.pi * R**2)  # sigma = M c / I, plus N / A for any direction
    assert load.span == pytest.approx(L, rel=1e-6)
    assert load.moment == pytest.approx(moment, rel=1e-6)
    assert load.stress == pytest.approx(sigma, rel=1e-6)
    assert load.deflection == pytest.approx(
        f * L**3 / (3 * PLA.youngs_modulus * i), rel=1e-6
    )  # F L^3 / 3 E I
    assert load.allowable == pytest.approx(PLA.yield_strength / SF)
    assert strength_faults([load]) == []  # 4.9 MPa against 25 MPa, 0.15 mm against 1.6 mm


def test_the_rods_own_weight_acts_at_its_middle():
    m = _rod_model()
    w = PLA.density * np.pi * R**2 * L
    (load,) = _loads(m, np.array([0.0, w, 0.0]))
    assert load.moment == pytest.approx(DYN * w * G * L / 2, rel=1e-6)  # M = w g L / 2
    # a load at a = L/2 on a span L: F a^2 (3 L - a) / (6 E I)
    ei = PLA.youngs_modulus * np.pi * R**4 / 4
    assert load.deflection == pytest.approx(w * G * (L / 2) ** 2 * (3 * L - L / 2) / (6 * ei), rel=1e-6)


def test_thin_strut_carrying_steel_is_refused_by_name():
    m = mujoco.MjModel.from_xml_string(
        """<mujoco><worldbody>
        <body name="support"><geom type="box" size="0.02 0.02 0.02" pos="-0.02 0 0"/></body>
        <body name="cw"><geom name="strut" type="box" size="0.06 0.0015 0.0002" pos="0.06 0 0"/>
          <geom name="steel" type="box" size="0.0115 0.0115 0.0115" pos="0.1315 0 0"/></body>
        </worldbody></mujoco>"""
    )
    masses = np.array([0.0, PLA.density * 0.12 * 0.003 * 0.0004, 0.18])
    load = next(p for p in _loads(m, masses) if p.part == "strut")
    faults = strength_faults([load])
    assert [f.code for f in faults] == ["overstressed", "too_flexible"]
    assert faults[0].message.startswith("part 'strut' of body 'cw' (pla, 120 mm span) carries ")
    assert "allowable 25.0 MPa" in faults[0].message
    assert load.stress > 1e9  # GPa in a 0.4 mm strut


def test_spring_tension_loads_its_post():
    # a post from the support along z, a zero-length spring from its tip to a fixed site 0.1 m away
    m = mujoco.MjModel.from_xml_string(
        """<mujoco><worldbody>
        <body name="support"><geom type="box" size="0.02 0.02 0.02" pos="0 0 -0.02"/>
          <site name="far" pos="0.1 0 0.05"/></body>
        <body name="post"><geom name="post" type="cylinder" fromto="0 0 0 0 0 0.05" size="0.006"/>
          <site name="tip" pos="0 0 0.05"/></body>
        </worldbody><tendon><spatial stiffness="500" springlength="0">
        <site site="tip"/><site site="far"/></spatial></tendon></mujoco>"""
    )
    tension = spring_tensions(m, m.qpos0[None, :])
    assert tension == pytest.approx([50.0])  # k L = 500 N/m x 0.1 m
    (load,) = part_loads(
        m,
        [2],
        masses=np.zeros(m.ngeom),
        material_of=lambda g: PLA,
        tensions=tension,
        dynamic_factor=DYN,
        safety_factor=lambda mat: SF,
        deflection_ratio=0.02,
        join_tol=1e-3,
    )
    i = np.pi * 0.006**4 / 4
    assert load.load == pytest.approx(50.0)  # the spring is not multiplied by the dynamic factor
    assert load.moment == pytest.approx(50.0 * 0.05, rel=1e-6)  # F x lever 50 mm
    assert load.deflection == pytest.approx(50.0 * 0.05**3 / (3 * PLA.youngs_modulus * i), rel=1e-6)


def test_polygon_sections_closed_form():
    b, h = 0.003, 0.0004
    rect = np.array([[-b / 2, -h / 2], [b / 2, -h / 2], [b / 2, h / 2], [-b / 2, h / 2]])
    area, centre, inertia, bending, _ = polygon_section([rect + [0.01, 0.02]])  # off the origin
    assert area == pytest.approx(b * h) and centre == pytest.approx([0.01, 0.02])
    assert inertia == pytest.approx(b * h**3 / 12)  # I = b h^3 / 12 about the weak axis
    assert bending == pytest.approx(np.hypot((h / 2) / (b * h**3 / 12), (b / 2) / (h * b**3 / 12)))
    # hollow square tube (outer B, inner a, hole wound clockwise): I = (B^4 - a^4) / 12
    big, small = 0.02, 0.016
    outer = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * big / 2
    hole = np.array([[-1, -1], [-1, 1], [1, 1], [1, -1]]) * small / 2
    area, _, inertia, _, _ = polygon_section([outer, hole])
    assert area == pytest.approx(big**2 - small**2) and inertia == pytest.approx((big**4 - small**4) / 12)


def test_a_mesh_beam_carries_what_the_same_box_carries():
    # the 3 x 0.4 mm x 120 mm strut as a mesh: its sections are the box's, so its clamp stress and
    # sag are the closed-form ones of the primitive strut
    hx, hy, hz = 0.06, 0.0015, 0.0002
    verts = " ".join(f"{x * hx} {y * hy} {z * hz}" for x in (-1, 1) for y in (-1, 1) for z in (-1, 1))
    faces = "0 2 1 1 2 3 4 5 6 5 7 6 0 1 4 1 5 4 2 6 3 3 6 7 0 4 2 2 4 6 1 3 5 3 7 5"
    xml = f"""<mujoco><asset><mesh name="strut" vertex="{verts}" face="{faces}"/></asset><worldbody>
        <body name="support"><geom type="box" size="0.02 0.02 0.02" pos="-0.02 0 0"/></body>
        <body name="cw"><geom name="strut" type="mesh" mesh="strut" pos="0.06 0 0"/>
          <geom name="steel" type="sphere" size="0.01" pos="0.13 0 0"/></body>
        </worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    masses = np.array([0.0, 0.0, 0.18])  # the steel only
    (mesh,) = [p for p in _loads(m, masses) if p.part == "strut"]
    box = beam_section(int(mujoco.mjtGeom.mjGEOM_BOX), np.array([hx, hy, hz]))
    f, lever = 0.18 * G, 0.13  # the weight 130 mm from the clamp
    sigma = DYN * f * lever * box.bending + DYN * f / box.area  # M c / I (worst direction) + N / A
    assert mesh.span == pytest.approx(0.12, rel=1e-6)
    assert mesh.stress == pytest.approx(sigma, rel=1e-3)
    ei = PLA.youngs_modulus * box.inertia  # beyond the end: F L^3 / 3 E I + F (a - L) L^2 / 2 E I
    assert mesh.deflection == pytest.approx(f * 0.12**3 / (3 * ei) + f * 0.01 * 0.12**2 / (2 * ei), rel=1e-3)
    assert [x.code for x in strength_faults([mesh])] == ["overstressed", "too_flexible"]
