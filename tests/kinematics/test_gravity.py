"""Batched closed-form gravity map and static torque with a payload."""

import mujoco
import numpy as np

from rle_design.kinematics import GravityMap, gravity_torque, model_from_mujoco, static_torque


def test_gravity_map_matches_pinocchio_on_a_branching_tree(branching_arm_xml):
    km = model_from_mujoco(mujoco.MjModel.from_xml_string(branching_arm_xml))
    q = np.random.default_rng(1).uniform(-np.pi, np.pi, size=(300, km.nq))
    batch = GravityMap(km)(q, chunk=64)
    ref = np.array([gravity_torque(km, p) for p in q])
    assert np.max(np.abs(batch - ref)) < 1e-12
    assert np.allclose(GravityMap(km)(q[0]), ref[0], atol=1e-12)


def test_single_link_gravity_is_m_g_l_sin():
    # hinge about y, COM at l = 0.2 m along x (horizontal at q = 0), m = 0.5 kg
    m = mujoco.MjModel.from_xml_string(
        '<mujoco><worldbody><body><joint axis="0 1 0"/><inertial pos="0.2 0 0" mass="0.5" '
        'diaginertia="1e-4 1e-4 1e-4"/></body></worldbody></mujoco>'
    )
    km = model_from_mujoco(m)
    q = np.linspace(-np.pi, np.pi, 37)[:, None]
    tau = GravityMap(km)(q)[:, 0]
    # rotation about +y by q lowers the COM for q > 0 (z = -l sin q): gravity's generalized force is
    # +m g l cos q, so the holding torque is g(q) = -m g l cos q
    assert np.allclose(tau, -0.5 * 9.81 * 0.2 * np.cos(q[:, 0]), atol=1e-12)


def test_static_torque_equals_gravity_of_the_model_with_the_payload_added(branching_arm_xml):
    plain = branching_arm_xml.replace(
        '<joint name="j3" axis="1 0 0"/>', '<joint name="j3" axis="1 0 0"/><site name="tool" pos="0.05 0 0"/>'
    )
    heavy = plain.replace(
        '<site name="tool" pos="0.05 0 0"/>',
        '<site name="tool" pos="0.05 0 0"/><body pos="0.05 0 0"><inertial pos="0 0 0" mass="0.07" '
        'diaginertia="1e-9 1e-9 1e-9"/></body>',
    )
    km = model_from_mujoco(mujoco.MjModel.from_xml_string(plain))
    km_heavy = model_from_mujoco(mujoco.MjModel.from_xml_string(heavy))
    q = np.array([0.3, -0.7, 1.1, 0.4])
    assert np.allclose(static_torque(km, q, 0.07, "tool"), gravity_torque(km_heavy, q), atol=1e-12)
