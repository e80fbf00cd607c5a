"""Actuator configs: compiled gains, limits and a closed-form static deflection."""

import math

import mujoco
import numpy as np
import pytest

from rle_design.errors import ConfigError, MissingElement
from rle_design.scene import MotorActuators, PhysicsOptions, PositionActuators, element_id

M, L, G = 1.0, 0.5, 9.81  # point mass [kg] on a massless arm of length L [m]; gravity [m/s^2]
# Horizontal pendulum: a hinge about y at the origin, the mass at x = L when q = 0.
PENDULUM = f"""<mujoco><worldbody>
  <body name="arm"><joint name="pitch" axis="0 1 0" damping="0"/>
    <inertial pos="{L} 0 0" mass="{M}" diaginertia="1e-6 1e-6 1e-6"/>
  </body>
</worldbody></mujoco>"""


def _settle(m: mujoco.MjModel, seconds: float = 4.0) -> mujoco.MjData:
    d = mujoco.MjData(m)
    mujoco.mj_step(m, d, int(seconds / m.opt.timestep))
    return d


def test_position_servo_static_deflection_is_m_g_l_over_kp():
    kp = 500.0  # [N m/rad]
    spec = mujoco.MjSpec.from_string(PENDULUM)
    PhysicsOptions(gravity=(0.0, 0.0, -G)).edit_spec(spec)
    PositionActuators(joints=("pitch",), kp=kp, kv=2.0 * math.sqrt(kp * M * L**2)).edit_spec(spec)
    m = spec.compile()
    d = _settle(m)  # ctrl = 0: hold the arm level
    q = float(d.qpos[0])
    # Gravity torque about +y at angle q is M g L cos(q) (the mass falls towards +q); the servo answers
    # -kp q. Equilibrium: kp q = M g L cos q, so for small angles q = M g L / kp (= 9.81e-3 rad here).
    small_angle = M * G * L / kp
    assert q == pytest.approx(small_angle, rel=1e-3)
    exact = small_angle
    for _ in range(50):  # fixed point of q = (M g L / kp) cos q
        exact = small_angle * math.cos(exact)
    assert q == pytest.approx(exact, rel=1e-6)
    assert abs(d.qvel[0]) < 1e-9


def test_position_gains_and_limits_in_the_compiled_model():
    spec = mujoco.MjSpec.from_string(PENDULUM)
    PositionActuators(
        joints=("pitch",), kp=80.0, kv=4.0, forcerange=(-12.0, 12.0), ctrlrange=(-1.0, 1.0), prefix="servo_"
    ).edit_spec(spec)
    m = spec.compile()
    a = element_id(m, "actuator", "servo_pitch")
    assert m.actuator_trnid[a, 0] == element_id(m, "joint", "pitch")
    assert (m.actuator_gainprm[a, 0], m.actuator_biasprm[a, 1], m.actuator_biasprm[a, 2]) == (
        80.0,
        -80.0,
        -4.0,
    )
    np.testing.assert_array_equal(m.actuator_forcerange[a], [-12.0, 12.0])
    np.testing.assert_array_equal(m.actuator_ctrlrange[a], [-1.0, 1.0])
    assert m.actuator_forcelimited[a] and m.actuator_ctrllimited[a]


def test_motor_torque_is_gear_times_ctrl():
    spec = mujoco.MjSpec.from_string(PENDULUM)
    MotorActuators(joints=("pitch",), gear=3.0, ctrlrange=(-2.0, 2.0)).edit_spec(spec)
    m = spec.compile()
    d = mujoco.MjData(m)
    d.ctrl[0] = 5.0  # clamped to 2
    mujoco.mj_forward(m, d)
    assert d.qfrc_actuator[0] == pytest.approx(6.0)
    assert m.actuator_biastype[0] == mujoco.mjtBias.mjBIAS_NONE


@pytest.mark.parametrize(
    "config, message",
    [
        (PositionActuators(joints=(), kp=1.0), "PositionActuators.joints must name at least one joint"),
        (
            PositionActuators(joints="pitch", kp=1.0),
            "PositionActuators.joints must be a tuple of names, got the string 'pitch'",
        ),
        (
            PositionActuators(joints=("a", "b", "a"), kp=1.0),
            "PositionActuators.joints lists a more than once",
        ),
        (PositionActuators(joints=("a",), kp=0.0), "PositionActuators.kp must be > 0, got 0.0"),
        (PositionActuators(joints=("a",), kp=1.0, kv=-1.0), "PositionActuators.kv must be >= 0, got -1.0"),
        (
            PositionActuators(joints=("a",), kp=1.0, forcerange=(5.0, -5.0)),
            "PositionActuators.forcerange must be (low, high) with low < high, got (5.0, -5.0)",
        ),
        (MotorActuators(joints=("a",), gear=-1.0), "MotorActuators.gear must be > 0, got -1.0"),
        (
            MotorActuators(joints=("a",), ctrlrange=(1.0,)),
            "MotorActuators.ctrlrange must have 2 entries, got 1",
        ),
    ],
)
def test_validate_refuses_with_exact_messages(config, message):
    with pytest.raises(ConfigError) as err:
        config.validate()
    assert str(err.value) == message


def test_missing_joint_and_taken_name_leave_the_spec_unchanged():
    spec = mujoco.MjSpec.from_string(PENDULUM)
    with pytest.raises(MissingElement) as err:
        PositionActuators(joints=("pitch", "roll"), kp=10.0).edit_spec(spec)
    assert str(err.value) == "joint 'roll' does not exist. Available joints: pitch"
    assert spec.compile().nu == 0  # 'pitch' was not actuated either
    MotorActuators(joints=("pitch",)).edit_spec(spec)
    with pytest.raises(ConfigError) as err:
        PositionActuators(joints=("pitch",), kp=10.0).edit_spec(spec)
    assert str(err.value) == "actuator 'pitch' already exists; set a prefix"
