"""Closed-form reference mechanisms for the stability toolkit (formula in each test)."""

import math

import mujoco
import numpy as np
import pytest

from rle_design.stability import (
    StabilityError,
    StabilityProbe,
    SupportLossMonitor,
    SupportSet,
    force_angle,
    sample_contacts,
    static_margin,
    support_polygon,
    tip_acceleration,
)
from rle_design.stability.contacts import support_normals

G = 9.81


def _box_on_wheels(half_x: float, half_y: float, com_h: float, mass: float = 40.0, r: float = 0.05) -> str:
    """A uniform box whose COM is at height com_h, standing on four sphere feet at (+-half_x, +-half_y)."""
    feet = "".join(
        f'<geom name="foot_{n}" type="sphere" size="{r}" pos="{sx * half_x} {sy * half_y} {r - com_h}" mass="0"/>'
        for n, sx, sy in (("fl", 1, 1), ("fr", 1, -1), ("rl", -1, 1), ("rr", -1, -1))
    )
    return f"""<mujoco><option timestep="0.002" cone="elliptic" noslip_iterations="5" integrator="implicitfast"/>
    <worldbody><geom name="floor" type="plane" size="5 5 .1" friction="3 0.005 0.0001"/>
    <body name="box" pos="0 0 {com_h}"><freejoint/>
    <geom name="hull" type="box" size="{half_x} {half_y} 0.05" mass="{mass}" contype="0" conaffinity="0"/>
    {feet}</body></worldbody></mujoco>"""


def _probe(model: mujoco.MjModel) -> StabilityProbe:
    supports = SupportSet.from_names(model, {n: [f"foot_{n}"] for n in ("fl", "fr", "rl", "rr")})
    return StabilityProbe(root_body=1, supports=supports)


def test_uniform_box_margin_is_half_shorter_support_dimension():
    # SSM of a centred COM on a rectangle 2a x 2b (b < a) is min(a, b) = b.
    a, b = 0.30, 0.20
    poly = support_polygon(np.array([[a, b], [a, -b], [-a, b], [-a, -b]]))
    assert static_margin(poly, np.array([0.0, 0.0, 0.4])) == pytest.approx(b, abs=1e-3)
    assert poly.area == pytest.approx(4 * a * b)


def test_point_mass_offset_moves_margin_by_closed_form():
    # Base M at the centre plus point mass m at x = e: COM x_c = m e / (M + m); margin = min(b, a - x_c).
    a, b, big, m, e = 0.30, 0.25, 40.0, 10.0, 0.5
    poly = support_polygon(np.array([[a, b], [a, -b], [-a, b], [-a, -b]]))
    x_c = m * e / (big + m)
    assert static_margin(poly, np.array([x_c, 0.0])) == pytest.approx(min(b, a - x_c), abs=1e-3)
    # outside the polygon the margin is negative: x_c = 0.4 > a gives a - x_c = -0.1
    assert static_margin(poly, np.array([0.4, 0.0])) == pytest.approx(-0.1, abs=1e-9)


def test_support_polygon_needs_three_points():
    with pytest.raises(StabilityError, match="at least 3 non-collinear contact points, got 2"):
        support_polygon(np.array([[0.0, 0.0], [1.0, 0.0], [0.5, 0.0]]))


def test_force_angle_static_and_at_tipping_acceleration():
    # Static: theta about the side axis = atan(d / h). Under a = g d / h toward that side, theta = 0.
    d, h, mass = 0.2, 0.4, 30.0
    pts = np.array([[0.3, d, 0], [0.3, -d, 0], [-0.3, d, 0], [-0.3, -d, 0]])
    com = np.array([0.0, 0.0, h])
    fa = force_angle(pts, com, mass)
    assert fa.min_theta == pytest.approx(math.atan2(d, h), abs=1e-9)
    # beta = theta |d_perp| |f|, with |d_perp| = d (moment arm of the vertical weight about the axis)
    assert fa.min_beta == pytest.approx(math.atan2(d, h) * d * mass * G, rel=1e-9)
    tip = force_angle(pts, com, mass, accel=np.array([0.0, -G * d / h, 0.0]))
    assert tip.min_theta == pytest.approx(0.0, abs=1e-9)
    beyond = force_angle(pts, com, mass, accel=np.array([0.0, -1.1 * G * d / h, 0.0]))
    assert beyond.min_theta < 0 and beyond.min_beta < 0


def test_box_at_rest_shares_weight_and_centre_of_pressure_is_below_com():
    model = mujoco.MjModel.from_xml_string(_box_on_wheels(0.3, 0.2, 0.3))
    data = mujoco.MjData(model)
    for _ in range(300):
        mujoco.mj_step(model, data)
    s = sample_contacts(model, data, _probe(model).supports)
    # Four symmetric supports: each carries m g / 4.
    np.testing.assert_allclose(s.normal, 40.0 * G / 4, rtol=0.02)
    np.testing.assert_allclose(s.cop, data.subtree_com[1][:2], atol=2e-3)


@pytest.mark.physics
def test_dynamic_battery_finds_tip_acceleration_g_d_over_h():
    # Rigid-body tipping about the side wheels under lateral base acceleration: a* = g d / h.
    d, h = 0.2, 0.3
    model = mujoco.MjModel.from_xml_string(_box_on_wheels(0.3, d, h))
    probe = _probe(model)

    def reset(data: mujoco.MjData) -> None:
        data.qpos[2] = h + 1e-4

    a = tip_acceleration(model, reset, probe, direction=np.array([0.0, 1.0, 0.0]), a_max=15.0)
    assert a is not None
    assert a == pytest.approx(G * d / h, rel=0.05)


def test_a_scenario_with_a_simulation_warning_names_it_and_a_calm_one_has_none():
    from rle_design.stability import Scenario, run_scenario

    model = mujoco.MjModel.from_xml_string(_box_on_wheels(0.3, 0.2, 0.3))
    probe = _probe(model)

    def blow_up(m, d, t):  # a non-finite generalised force: MuJoCo flags bad qacc and resets
        if t > 0.1:
            d.qfrc_applied[:] = np.nan

    calm = run_scenario(model, mujoco.MjData(model), Scenario("calm", 0.3), probe)
    bad = run_scenario(model, mujoco.MjData(model), Scenario("nan", 0.3, control=blow_up), probe)
    assert calm.warning is None and not calm.tipped
    assert bad.warning is not None and "mjWARN_BADQACC" in bad.warning
    assert bad.t[-1] < 0.3 - 1e-9  # the scenario ended at the warning instead of reading on


def test_support_normals_per_contact_loop_equals_the_vectorised_sums():
    # The few-contact loop of support_normals must give bit for bit what sample_contacts sums with
    # np.add.at (same order of additions): sum_i max(f_i, 0) per support, m g / 4 each at rest.
    model = mujoco.MjModel.from_xml_string(_box_on_wheels(0.3, 0.2, 0.3))
    data = mujoco.MjData(model)
    supports = _probe(model).supports
    data.qvel[3:6] = (0.4, -0.3, 0.2)  # rocking: the four loads differ
    seen = 0
    for _ in range(400):
        mujoco.mj_step(model, data)
        looped = support_normals(model, data, supports)
        np.testing.assert_array_equal(looped, sample_contacts(model, data, supports).normal)
        seen += int(np.count_nonzero(looped) > 0 and np.ptp(looped) > 1.0)
    assert seen > 10, "the loads never differed: the comparison was not exercised"
    np.testing.assert_allclose(looped.sum(), 40.0 * G, rtol=0.02)


def test_support_loss_monitor_times_the_longest_run_below_the_threshold():
    # 4 supports sharing 40 N: threshold = 0.05 * 40 / 4 = 0.5 N. Support 0 carries 0.1 N from
    # t = 0.10 s to t = 0.34 s (samples every 0.01 s): its longest run is 0.34 - 0.10 = 0.24 s.
    m = SupportLossMonitor(weight=40.0, n_supports=4, fraction=0.05, min_duration=0.1)
    assert m.threshold == pytest.approx(0.5)
    for k in range(60):
        t = k / 100
        low = 0.1 if 10 <= k <= 34 else 10.0
        m.update(t, np.array([low, 10.0, 10.0 - k / 100, 10.0]))
    np.testing.assert_allclose(m.longest, [0.24, 0.0, 0.0, 0.0], atol=1e-12)
    assert m.lost and m.longest_loss == pytest.approx(0.24)
    np.testing.assert_allclose(m.min_force, [0.1, 10.0, 9.41, 10.0])
    short = SupportLossMonitor(weight=40.0, n_supports=4, min_duration=0.1)
    for k in range(20):  # 0.05 s below the threshold: not a sustained loss
        short.update(k / 100, np.array([0.1 if k < 6 else 5.0, 5.0, 5.0, 5.0]))
    assert not short.lost and short.longest_loss == pytest.approx(0.05)
    short.update(0.2, np.array([np.nan, 5.0, 5.0, 5.0]))  # a NaN sample is kept, as np.minimum keeps it
    assert np.isnan(short.min_force[0])
