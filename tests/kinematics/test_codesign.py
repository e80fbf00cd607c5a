"""The co-design optimiser recovers the closed-form balance of reference mechanisms.

Link on a hinge about +y through the origin, pointing up at q = 0 (angle from the upward vertical
theta = q). Bare holding torque g(theta) = -m g l sin(theta).

* zero-length spring from (0, 0, a) on the world to (0, 0, b) on the link: balanced at every angle
  when k a b = m g l;
* counterweight m_c at distance r_c opposite masses m_i at distances l_i: m_c r_c = sum m_i l_i;
  with a printed arm of density lambda from the axis: m_c r_c + lambda r_c^2 / 2 = sum m_i l_i.
"""

import mujoco
import numpy as np
import pytest
from mujoco import MjSpec

from rle_design.kinematics import model_from_mujoco
from rle_design.kinematics.codesign import CodesignError, CounterweightSlot, SpringSlot, optimise_balance

G = 9.81
M1, L1 = 0.12, 0.15  # link mass [kg] and centre-of-mass height [m]
M2, L2 = 0.05, 0.22  # a second part fixed on the link
GRID = np.linspace(-2.5, 2.5, 11)[:, None]


def _link(second_part: bool = False) -> mujoco.MjModel:
    spec = MjSpec()
    link = spec.worldbody.add_body(name="link")
    link.add_joint(name="hinge", type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 1, 0])
    link.add_geom(size=[0.01, 0, 0], pos=[0, 0, L1], mass=M1)
    if second_part:
        part = link.add_body(name="part", pos=[0, 0, L2])
        part.add_geom(size=[0.01, 0, 0], mass=M2)
    return spec.compile()


def test_zero_length_spring_recovers_k_a_b_equals_m_g_l():
    km = model_from_mujoco(_link())
    a, b = 0.04, 0.05
    slot = SpringSlot("s", 0, (0, 0, a), (0, 0, a), 1, (0, 0, b), (0, 0, b), max_stiffness=1000.0)
    res = optimise_balance(km, GRID, springs=(slot,))
    k = res.springs["s"][2]
    assert abs(k * a * b - M1 * G * L1) <= 1e-6 * M1 * G * L1  # k a b = m g l
    assert res.worst_residual < 1e-6


def test_a_catalog_rate_is_kept_and_the_attachment_moves_instead():
    km = model_from_mujoco(_link())
    a, k = 0.04, 968.018  # a catalog rate [N/m]
    b = M1 * G * L1 / (k * a)  # k a b = m g l: 4.56 mm
    slot = SpringSlot("s", 0, (0, 0, a), (0, 0, a), 1, (0, 0, 0.001), (0, 0, 0.02), k, min_stiffness=k)
    res = optimise_balance(km, GRID, springs=(slot,))
    _, attach, k_out = res.springs["s"]
    assert k_out == k and abs(attach[2] - b) <= 1e-6 * b and res.worst_residual < 1e-6
    with pytest.raises(CodesignError, match="not ordered"):
        optimise_balance(
            km, GRID, springs=(SpringSlot("s", 0, (0, 0, a), (0, 0, a), 1, (0, 0, b), (0, 0, b), 1.0, 2.0),)
        )


def test_free_spring_anchors_balance_within_their_boxes():
    km = model_from_mujoco(_link())
    slot = SpringSlot("s", 0, (-0.01, 0, 0.02), (0.01, 0, 0.06), 1, (-0.01, 0, 0.03), (0.01, 0, 0.08), 200.0)
    res = optimise_balance(km, GRID, springs=(slot,))
    anchor, attach, k = res.springs["s"]
    assert res.worst_residual < 1e-6
    assert k <= 200.0 + 1e-9 and np.all(anchor >= [-0.01 - 1e-9, 0, 0.02 - 1e-9])
    # k (a x b)_y-free form: for collinear vertical anchors the balance is still k a_z b_z = m g l.
    assert abs(k * anchor[2] * attach[2] - M1 * G * L1) < 1e-5


def test_counterweight_recovers_m_c_r_c_equals_sum_m_i_l_i():
    km = model_from_mujoco(_link(second_part=True))
    r_c = 0.08
    slot = CounterweightSlot("cw", 1, (0, 0, -r_c), (0, 0, -r_c), max_mass=2.0)
    res = optimise_balance(km, GRID, counterweights=(slot,))
    _, m_c, arm = res.counterweights["cw"]
    assert abs(m_c * r_c - (M1 * L1 + M2 * L2)) < 1e-6  # m_c r_c = sum m_i l_i
    assert arm == pytest.approx(0.0, abs=1e-9) and res.worst_residual < 1e-6


def test_printed_arm_mass_is_counted_in_the_balance_and_the_added_mass():
    km = model_from_mujoco(_link(second_part=True))
    r_c, lam = 0.08, 0.4  # lambda [kg/m]
    slot = CounterweightSlot("cw", 1, (0, 0, -r_c), (0, 0, -r_c), 2.0, arm_density=lam)
    res = optimise_balance(km, GRID, counterweights=(slot,))
    _, m_c, arm = res.counterweights["cw"]
    assert abs(m_c * r_c + lam * r_c**2 / 2 - (M1 * L1 + M2 * L2)) < 1e-6
    assert arm == pytest.approx(lam * r_c, rel=1e-6)
    assert res.added_mass == pytest.approx(m_c + lam * r_c, rel=1e-6)


def test_mass_weight_pushes_the_counterweight_to_the_far_end_of_its_box():
    km = model_from_mujoco(_link(second_part=True))
    slot = CounterweightSlot("cw", 1, (0, 0, -0.12), (0, 0, -0.03), max_mass=2.0)
    res = optimise_balance(km, GRID, counterweights=(slot,), mass_weight=1e-3)
    pos, m_c, _ = res.counterweights["cw"]
    assert pos[2] == pytest.approx(-0.12, abs=1e-6)
    assert m_c * 0.12 == pytest.approx(M1 * L1 + M2 * L2, abs=1e-5)


def test_a_mass_budget_too_small_leaves_the_closed_form_residual():
    km = model_from_mujoco(_link(second_part=True))
    r_c, budget = 0.08, 0.2
    slot = CounterweightSlot("cw", 1, (0, 0, -r_c), (0, 0, -r_c), max_mass=2.0)
    res = optimise_balance(km, GRID, counterweights=(slot,), mass_budget=budget)
    # Worst residual at the grid's largest |sin(theta)|: (sum m_i l_i - m_c r_c) g max|sin|.
    expected = (M1 * L1 + M2 * L2 - budget * r_c) * G * np.max(np.abs(np.sin(GRID)))
    assert res.counterweights["cw"][1] == pytest.approx(budget, abs=1e-6)
    assert res.worst_residual == pytest.approx(expected, rel=1e-5)


def test_bad_slots_are_refused_by_name():
    km = model_from_mujoco(_link())
    with pytest.raises(CodesignError, match="slot 'cw'"):
        optimise_balance(km, GRID, counterweights=(CounterweightSlot("cw", 1, (0, 0, 1), (0, 0, 0), 1.0),))
    with pytest.raises(CodesignError, match="joint ids"):
        optimise_balance(km, GRID, counterweights=(CounterweightSlot("cw", 7, (0, 0, 0), (0, 0, 0), 1.0),))
    with pytest.raises(CodesignError, match="coordinates per pose"):
        optimise_balance(km, np.zeros((3, 2)))
