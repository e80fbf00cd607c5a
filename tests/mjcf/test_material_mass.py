"""Mass where the material is: closed-form bodies pass, displaced or mis-dense inertials are named."""

import mujoco
import numpy as np
import pytest

from rle_design.catalog import load_catalog
from rle_design.mjcf.geom_solid import geom_volume
from rle_design.mjcf.material_mass import geom_masses, material_findings, material_for

STEEL = load_catalog("materials").get("steel")
PLA = load_catalog("materials").get("pla")


def _model(body: str) -> tuple[mujoco.MjSpec, mujoco.MjModel]:
    spec = mujoco.MjSpec.from_string(f"<mujoco><worldbody>{body}</worldbody></mujoco>")
    return spec, spec.compile()


def _codes(body: str) -> list[str]:
    spec, m = _model(body)
    return [f.code for f in material_findings(spec, m, [1])]


def test_box_closed_form():
    a, b, c, rho = 0.04, 0.02, 0.01, PLA.density
    mass = rho * a * b * c  # m = rho a b c
    ixx, iyy, izz = mass * (b**2 + c**2) / 12, mass * (a**2 + c**2) / 12, mass * (a**2 + b**2) / 12
    body = (
        f'<body name="box"><inertial pos="0 0 0" mass="{mass:.9g}" diaginertia="{ixx:.9g} {iyy:.9g} {izz:.9g}"/>'
        f'<geom type="box" size="{a / 2} {b / 2} {c / 2}" density="{rho}"/></body>'
    )
    assert _codes(body) == []
    spec, m = _model(body)
    assert geom_volume(m, 0) == pytest.approx(a * b * c, rel=1e-12)
    assert geom_masses(spec, m)[0] == pytest.approx(mass, rel=1e-12)
    # the same inertial with the inertia of a cube of the same mass: 1 % is the tolerance
    wrong = body.replace(f"{ixx:.9g} {iyy:.9g}", f"{ixx * 1.5:.9g} {iyy:.9g}")
    assert _codes(wrong) == ["inertial.inertia_mismatch"]


def test_cylinder_closed_form():
    r, h, rho = 0.01, 0.05, STEEL.density
    mass = rho * np.pi * r**2 * h  # m = rho pi r^2 h
    i_axis, i_perp = mass * r**2 / 2, mass * (3 * r**2 + h**2) / 12  # I_z = m r^2/2, I_x = m (3 r^2 + h^2)/12
    body = (
        f'<body name="c"><inertial pos="0 0 0" mass="{mass:.9g}" diaginertia="{i_perp:.9g} {i_perp:.9g} {i_axis:.9g}"/>'
        f'<geom type="cylinder" size="{r} {h / 2}" mass="{mass:.9g}"/></body>'
    )
    assert _codes(body) == []
    assert _codes(body.replace(f'mass="{mass:.9g}"/>', f'mass="{mass * 1.01:.9g}"/>')) == [
        "material.too_dense",
        "inertial.mass_mismatch",
    ]


def test_two_part_body_closed_form():
    # a PLA rod (0.1 m along x, r 5 mm) with a steel sphere (r 12 mm) at its end:
    # m = m_r + m_s, x_c = (m_r 0.05 + m_s 0.1) / m, I_yy about the COM by the parallel-axis theorem
    r, length, rs = 0.005, 0.1, 0.012
    m_r = PLA.density * np.pi * r**2 * length
    m_s = STEEL.density * 4 / 3 * np.pi * rs**3
    mass = m_r + m_s
    xc = (m_r * length / 2 + m_s * length) / mass
    iyy = (
        m_r * (3 * r**2 + length**2) / 12
        + m_r * (length / 2 - xc) ** 2
        + 2 / 5 * m_s * rs**2
        + m_s * (length - xc) ** 2
    )
    ixx = m_r * r**2 / 2 + 2 / 5 * m_s * rs**2
    geoms = (
        f'<geom type="cylinder" fromto="0 0 0 {length} 0 0" size="{r}" density="{PLA.density}"/>'
        f'<geom type="sphere" pos="{length} 0 0" size="{rs}" density="{STEEL.density}"/>'
    )
    inertial = f'<inertial pos="{xc:.9g} 0 0" mass="{mass:.9g}" diaginertia="{ixx:.9g} {iyy:.9g} {iyy:.9g}"/>'
    assert _codes(f'<body name="cw">{inertial}{geoms}</body>') == []
    spec, m = _model(f'<body name="cw">{geoms}</body>')
    assert m.body_mass[1] == pytest.approx(mass, rel=1e-9)
    assert m.body_ipos[1][0] == pytest.approx(xc, rel=1e-9)
    # the same mass declared 0.2 m away, outside the parts: the displaced counterweight
    far = inertial.replace(f'pos="{xc:.9g} 0 0"', 'pos="0.3 0 0"')
    spec, m = _model(f'<body name="cw">{far}{geoms}</body>')
    found = material_findings(spec, m, [1])
    # (the inertia is about the centre of mass, so it still agrees)
    assert [f.code for f in found] == ["inertial.com_mismatch", "inertial.com_outside"]
    assert found[0].message.startswith("body 'cw': declared centre of mass [0.3, 0.0, 0.0] m is ")
    assert "outside its geometry's convex hull" in found[1].message


def test_density_edges_are_exact():
    lo, hi = STEEL.density_range
    assert material_for(hi, [STEEL]) is STEEL and material_for(lo, [STEEL]) is STEEL
    assert material_for(hi * 1.01, [STEEL]) is None  # the 1 % over steel
    assert material_for(lo * 0.999, [STEEL]) is None
    sphere = '<body name="s"><geom type="sphere" size="0.01" density="{}"/></body>'
    assert _codes(sphere.format(hi)) == []
    assert _codes(sphere.format(hi * 1.01)) == ["material.too_dense"]
    assert _codes(sphere.format(PLA.density_range[0] * 0.99)) == ["material.too_light"]
    assert _codes(sphere.format(5000)) == ["material.density"]  # between aluminium and steel
    assert _codes(sphere.format(0)) == []  # massless parts allowed unless the family says otherwise
    spec, m = _model(sphere.format(0))
    assert [f.code for f in material_findings(spec, m, [1], massless_ok=False)] == ["material.too_light"]


def test_message_names_the_part_and_the_ranges():
    spec, m = _model(
        '<body name="s"><geom name="cube" type="box" size="0.01 0.01 0.01" mass="0.0634"/></body>'
    )
    (f,) = material_findings(spec, m, [1])
    assert f.message.startswith(
        "part 'cube' of body 's' has 0.0634 kg in 8 cm^3 (7925 kg/m^3): no catalog material"
    )
    assert "steel 7800-7870" in f.message and "pla 1240-1250" in f.message


def test_a_mass_without_parts_is_named():
    spec, m = _model(
        '<body name="ghost"><inertial pos="0 0 0" mass="2.5" diaginertia="1e-4 1e-4 1e-4"/></body>'
    )
    found = material_findings(spec, m, [1])
    assert [(f.code, f.message) for f in found if f.code == "inertial.com_outside"] == [
        ("inertial.com_outside", "body 'ghost': declares 2.5 kg but has no parts (solid geoms) to carry it")
    ]


@pytest.mark.parametrize(
    "trick",
    ['<compiler inertiagrouprange="0 2"/>', ""],
    ids=["geom_group_left_out", "shell_inertia"],
)
def test_a_part_left_out_of_the_mass_is_named(trick):
    # a 100 mm PLA rod whose mass MuJoCo leaves out (group 3 outside inertiagrouprange) or computes as
    # a thin shell: the body's mass is not its geometry's
    geom = '<geom type="box" size="0.05 0.01 0.01" density="1240" {}/>'
    extra = 'group="3"' if trick else 'shellinertia="true"'
    xml = f"<mujoco>{trick}<worldbody><body name='rod'>{geom.format(extra)}</body></worldbody></mujoco>"
    spec = mujoco.MjSpec.from_string(xml)
    m = spec.compile()
    codes = [f.code for f in material_findings(spec, m, [1])]
    assert "inertial.mass_mismatch" in codes
