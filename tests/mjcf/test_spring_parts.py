"""Springs as catalog parts: the catalog follows the spring formulas, and a model's springs are matched
and checked against their ratings on a reference mechanism with a closed-form length."""

import mujoco
import numpy as np
import pytest

from rle_design.catalog import load_catalog
from rle_design.mjcf.spring_parts import match_rate, spring_mass, spring_parts, spring_rating_faults

WEAK = "cs-d1.6-D12-n40"  # 939.852 N/m, rated 56.2 N


def _sut(cat, d: float) -> float:
    """Music-wire tensile strength S_ut = A / d[mm]^m [Pa] (Shigley Table 10-4)."""
    return cat.extra["tensile_strength_A"] / (d * 1e3) ** cat.extra["tensile_strength_exponent"]


@pytest.mark.parametrize("entry", load_catalog("springs").entries, ids=lambda e: e.id)
def test_compression_springs_follow_the_formulas(entry):
    cat = load_catalog("springs")
    d, big_d, na = entry.wire_diameter, entry.mean_diameter, entry.active_coils
    c = big_d / d
    rate = d**4 * cat.extra["shear_modulus"] / (8 * big_d**3 * na)  # k = d^4 G / (8 D^3 N_a)
    kb = (4 * c + 2) / (4 * c - 3)  # Bergstraesser factor
    stress_limit = np.pi * d**3 * cat.extra["allowable_shear_fraction"] * _sut(cat, d) / (8 * kb * big_d)
    solid = d * (na + 2)  # squared and ground ends
    max_force = min(stress_limit, rate * (entry.free_length - solid))
    mass = cat.extra["density"] * np.pi**2 * d**2 * big_d * (na + 2) / 4
    assert entry.rate == pytest.approx(rate, rel=1e-5)
    assert entry.solid_length == pytest.approx(solid, rel=1e-9)
    assert entry.max_force == pytest.approx(max_force, rel=1e-3)
    assert entry.max_stroke == pytest.approx(max_force / rate, rel=1e-3)
    assert entry.mass == pytest.approx(mass, rel=1e-3)


@pytest.mark.parametrize("entry", load_catalog("torsion_springs").entries, ids=lambda e: e.id)
def test_torsion_springs_follow_the_formulas(entry):
    cat = load_catalog("torsion_springs")
    d, big_d, nb = entry.wire_diameter, entry.mean_diameter, entry.body_coils
    c = big_d / d
    rate = d**4 * cat.extra["youngs_modulus"] / (64 * big_d * nb)  # k = d^4 E / (64 D N_b) per rad
    ki = (4 * c * c - c - 1) / (4 * c * (c - 1))
    moment = np.pi * d**3 * cat.extra["allowable_bending_fraction"] * _sut(cat, d) / (32 * ki)
    assert entry.rate == pytest.approx(rate, rel=1e-5)
    assert entry.max_moment == pytest.approx(moment, rel=1e-3)
    assert entry.max_angle == pytest.approx(moment / rate, rel=1e-3)
    assert entry.mass == pytest.approx(cat.extra["density"] * np.pi**2 * d**2 * big_d * nb / 4, rel=1e-3)


def test_rates_identify_their_entry():
    for kind in ("springs", "torsion_springs"):
        rates = [e.rate for e in load_catalog(kind)]
        assert len(set(rates)) == len(rates)  # a rate names one entry
        for e in load_catalog(kind):
            assert match_rate(kind, e.rate) is e
            assert match_rate(kind, e.rate * (1 + 1e-4)) is None


def _lever(a: float, b: float, stiffness: float, springlength: str = "0", joint: str = "") -> mujoco.MjModel:
    """A hinge (axis y) at the origin; a spring from a site ``a`` above it to a site ``b`` out along
    the link: L(theta)^2 = a^2 + b^2 + 2 a b sin(theta) (the link's x axis turns towards -z)."""
    return mujoco.MjModel.from_xml_string(
        f"""<mujoco><compiler angle="radian"/><worldbody><site name="top" pos="0 0 {a}"/>
        <body name="link"><joint name="hinge" axis="0 1 0" range="-3.1 3.1" {joint}/>
          <geom type="box" size="{b} 0.01 0.01" pos="{b / 2} 0 0" mass="0.1"/>
          <site name="tip" pos="{b} 0 0"/></body></worldbody>
        <tendon><spatial name="spring" stiffness="{stiffness}" springlength="{springlength}">
          <site site="top"/><site site="tip"/></spatial></tendon></mujoco>"""
    )


POSES = np.linspace(-3.0, 3.0, 61)[:, None]


def test_the_lever_length_is_the_closed_form():
    m = _lever(0.04, 0.03, load_catalog("springs").get(WEAK).rate)
    d = mujoco.MjData(m)
    for (theta,) in POSES:
        d.qpos[0] = theta
        mujoco.mj_fwdPosition(m, d)
        assert d.ten_length[0] == pytest.approx(np.sqrt(0.04**2 + 0.03**2 + 2 * 0.04 * 0.03 * np.sin(theta)))


def test_a_spring_within_its_rating_passes_and_its_mass_counts():
    entry = load_catalog("springs").get(WEAK)
    # largest tension k (a + b) = 939.852 x 0.05 = 47.0 N < 56.2 N
    m = _lever(0.025, 0.025, entry.rate)
    assert spring_rating_faults(m, POSES) == []
    (part,) = spring_parts(m)
    assert part.entry is entry and spring_mass(m) == entry.mass


def test_an_overloaded_spring_is_refused_at_its_worst_pose():
    entry = load_catalog("springs").get(WEAK)
    # largest tension k (a + b) = 939.852 x 0.08 = 75.2 N > 56.2 N, at sin(theta) = 1
    (fault,) = spring_rating_faults(_lever(0.04, 0.04, entry.rate), POSES)
    assert fault.code == "overload" and WEAK in fault.message
    theta = POSES[fault.pose, 0]
    assert entry.rate * np.sqrt(0.0032 + 0.0032 * np.sin(theta)) == pytest.approx(75.2, abs=0.1)
    assert "75.2 N" in fault.message


def test_an_ideal_stiffness_is_no_part():
    (fault,) = spring_rating_faults(_lever(0.025, 0.025, 950.0), POSES)
    assert fault.code == "catalog" and "950 N/m" in fault.message and "cs-d2.5-D20-n50" in fault.message
    assert spring_mass(_lever(0.025, 0.025, 950.0)) == 0.0


def test_a_cable_cannot_push_but_may_go_slack():
    rate = load_catalog("springs").get(WEAK).rate
    # L ranges over |a - b| .. a + b = 0.005 .. 0.045 m; a 30 mm spring length would push below it
    (fault,) = spring_rating_faults(_lever(0.025, 0.02, rate, springlength="0.03"), POSES)
    assert fault.code == "push"
    assert spring_rating_faults(_lever(0.025, 0.02, rate, springlength="0 0.03"), POSES) == []


def test_torsion_springs_are_matched_and_rated_over_the_joint_range():
    cat = load_catalog("torsion_springs")
    short, long_ = cat.get("ts-d1.5-D12-n5"), cat.get("ts-d1.5-D12-n10")  # 1.886 / 3.772 rad
    # the range -3.1 .. 3.1 rad deflects a spring with springref 0 by up to 3.1 rad
    ok = _lever(0.025, 0.02, 939.852, joint=f'stiffness="{long_.rate}" springref="0"')
    assert spring_rating_faults(ok, POSES) == []
    assert spring_mass(ok) == pytest.approx(long_.mass + load_catalog("springs").get(WEAK).mass)
    (fault,) = spring_rating_faults(_lever(0.025, 0.02, 939.852, joint=f'stiffness="{short.rate}"'), POSES)
    assert fault.code == "overload" and "3.100 rad" in fault.message
    (fault,) = spring_rating_faults(_lever(0.025, 0.02, 939.852, joint='stiffness="0.2"'), POSES)
    assert fault.code == "catalog" and "torsion" in fault.message
