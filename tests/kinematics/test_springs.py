"""Closed-form reference mechanisms: zero-length springs, counterweights, torsion springs.

Single link on a hinge about +y through the origin; at q = 0 it points straight up, so the angle
from the upward vertical is theta = q. COM at distance l, mass m. MuJoCo's holding residual is
r_mj(q) = qfrc_bias - qfrc_passive = -(m g l sin(theta) - tau_spring(theta)).
"""

import mujoco
import numpy as np
import pytest

from rle_design.kinematics import (
    GravityMap,
    counterweight_moment,
    model_from_mujoco,
    spring_torque,
    springs_from_mujoco,
    torsion_spring_residual,
    zero_length_spring_residual,
    zero_length_spring_torque,
)

M, L, G = 0.12, 0.15, 9.81
A, B = 0.04, 0.05
K = M * G * L / (A * B)  # k a b = m g l
THETA = np.linspace(-3.0, 3.0, 121)


def _link(extra_world: str = "", extra_link: str = "", joint: str = "", springlength: str = "0") -> str:
    return f"""
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <site name="anchor" pos="0 0 {A}"/>{extra_world}
    <body name="link">
      <joint name="hinge" axis="0 1 0" {joint}/>
      <inertial pos="0 0 {L}" mass="{M}" diaginertia="1e-4 1e-4 1e-4"/>
      <site name="attach" pos="0 0 {B}"/>{extra_link}
    </body>
  </worldbody>
  <tendon>
    <spatial name="spring" stiffness="{K!r}" springlength="{springlength}">
      <site site="anchor"/><site site="attach"/>
    </spatial>
  </tendon>
</mujoco>"""


def _mujoco_residual(m: mujoco.MjModel) -> np.ndarray:
    d = mujoco.MjData(m)
    out = []
    for q in THETA:
        d.qpos[0] = q
        mujoco.mj_forward(m, d)
        out.append(d.qfrc_bias[0] - d.qfrc_passive[0])
    return np.array(out)


def _analytic_residual(m: mujoco.MjModel) -> np.ndarray:
    km = model_from_mujoco(m)
    springs = springs_from_mujoco(m, km)
    g = GravityMap(km)(THETA[:, None])[:, 0]
    return g - np.array([spring_torque(km, springs, [q])[0] for q in THETA])


def test_zero_length_spring_balances_the_link_at_every_angle():
    m = mujoco.MjModel.from_xml_string(_link())
    assert np.max(np.abs(_mujoco_residual(m))) < 1e-9
    assert np.max(np.abs(_analytic_residual(m))) < 1e-9
    assert np.max(np.abs(zero_length_spring_residual(M, L, K, A, B, THETA))) < 1e-12


def test_free_length_leaves_the_closed_form_error_k_a_b_sin_l0_over_l():
    l0 = 0.02
    m = mujoco.MjModel.from_xml_string(_link(springlength=f"{l0} {l0}"))
    length = np.sqrt(A * A + B * B - 2 * A * B * np.cos(THETA))
    expected = K * A * B * np.sin(THETA) * l0 / length  # m g l sin - k a b sin (1 - L0/L)
    assert np.allclose(
        zero_length_spring_residual(M, L, K, A, B, THETA, free_length=l0), expected, atol=1e-12
    )
    assert np.allclose(-_mujoco_residual(m), expected, atol=1e-9)
    assert np.allclose(-_analytic_residual(m), expected, atol=1e-9)
    assert np.max(np.abs(expected)) > 1e-2  # the error is not negligible


def test_tension_only_spring_is_slack_below_its_free_length():
    l0 = 0.03  # longer than |a - b| = 0.01: slack near upright
    m = mujoco.MjModel.from_xml_string(_link(springlength=f"0 {l0}"))
    tau = zero_length_spring_torque(K, A, B, THETA, free_length=l0, tension_only=True)
    expected = M * G * L * np.sin(THETA) - tau
    assert np.allclose(-_mujoco_residual(m), expected, atol=1e-9)
    assert np.allclose(-_analytic_residual(m), expected, atol=1e-9)
    length = np.sqrt(A * A + B * B - 2 * A * B * np.cos(THETA))
    assert np.all(tau[length < l0] == 0.0)


def test_counterweight_with_mc_rc_equal_m_l_zeroes_the_gravity_torque():
    rc = 0.06
    mc = counterweight_moment([M], [L]) / rc
    cw = f'<body name="cw" pos="0 0 {-rc}"><inertial pos="0 0 0" mass="{mc!r}" diaginertia="1e-6 1e-6 1e-6"/></body>'
    m = mujoco.MjModel.from_xml_string(_link(extra_link=cw).replace(f'stiffness="{K!r}"', 'stiffness="0"'))
    km = model_from_mujoco(m)
    assert np.max(np.abs(GravityMap(km)(THETA[:, None]))) < 1e-12
    assert np.max(np.abs(_mujoco_residual(m))) < 1e-12


@pytest.mark.parametrize("k_t, theta0", [(0.1, 0.0), (0.25, 0.3)])
def test_torsion_spring_residual_is_mgl_sin_minus_k_theta(k_t, theta0):
    m = mujoco.MjModel.from_xml_string(
        _link(joint=f'stiffness="{k_t}" springref="{theta0}"').replace(f'stiffness="{K!r}"', 'stiffness="0"')
    )
    expected = torsion_spring_residual(M * G * L, k_t, THETA, theta0)
    assert np.allclose(-_mujoco_residual(m), expected, atol=1e-12)
    assert np.allclose(-_analytic_residual(m), expected, atol=1e-12)
