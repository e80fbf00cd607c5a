"""The mobile Panda and its 12-D controller, against closed forms of its servos."""

import math

import mujoco
import numpy as np
import pytest

from rle_design.control.layout import POS_STEP
from rle_design.control.mobile import TORSO_STEP, MobileManipulatorEnv
from rle_design.scene.arena import Arena
from rle_design.scene.mobile_panda import BASE_FRICTION, BASE_MASSES, HIDDEN_GROUP, MobilePandaConfig
from rle_design.scene.robots import PANDA

NAMES = MobilePandaConfig(site="mount").names
TORSO0 = 0.1


def _xml() -> str:
    spec = mujoco.MjSpec()
    Arena().edit_spec(spec)
    spec.nuserdata = 7
    spec.worldbody.add_site(name="mount", pos=[0, 0, 0], quat=[math.cos(0.3), 0, 0, math.sin(0.3)])
    MobilePandaConfig(site="mount").edit_spec(spec)
    model = spec.compile()
    data = mujoco.MjData(model)
    for j, q in zip(NAMES.joints, PANDA.home):
        data.qpos[model.jnt_qposadr[model.joint(j).id]] = q
    data.qpos[model.jnt_qposadr[model.joint(NAMES.torso_joint).id]] = TORSO0
    data.ctrl[model.actuator(NAMES.torso_actuator).id] = TORSO0
    spec.add_key(name="initial", qpos=data.qpos.tolist(), ctrl=data.ctrl.tolist())
    return spec.to_xml()


@pytest.fixture(scope="module")
def env():
    e = MobileManipulatorEnv(xml=_xml(), image_size=None)
    model = e.build()
    e.prepare(model)
    data = mujoco.MjData(model)
    return e, model, data


def _act(**kw) -> np.ndarray:
    a = np.zeros(12)
    a[6] = -1.0
    a[11] = -1.0
    for k, v in kw.items():
        idx = {"x": 0, "gripper": 6, "fwd": 7, "left": 8, "yaw": 9, "torso": 10, "mode": 11}[k]
        a[idx] = v
    return a


def test_composition(env):
    e, model, data = env
    assert model.nu == 13 and [model.camera(c).id for c in NAMES.cameras]
    base = sum(model.body_mass[model.body(NAMES.prefix + b).id] for b in BASE_MASSES)
    assert base == pytest.approx(sum(BASE_MASSES.values()))
    assert model.jnt_range[model.joint(NAMES.joints[0]).id] == pytest.approx([-2.8973, 2.8973])
    meshes = [
        g
        for g in range(model.ngeom)
        if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH
        and model.geom_contype[g] == 0
        and model.geom_conaffinity[g] == 0
    ]
    assert meshes and all(model.geom_group[g] == HIDDEN_GROUP for g in meshes)


def test_base_velocity_servo_settles_at_command_minus_friction_over_gain(env):
    """Velocity servo force kv (v_cmd - v) against Coulomb friction f: steady v = v_cmd - f / kv, along
    the base's heading (the mount is turned 0.6 rad)."""
    e, model, data = env
    e.reset(model, data)
    a = _act(fwd=0.5, mode=1.0)
    for _ in range(20):
        e.step(model, data, a)
    p0, t0 = data.xpos[model.body(NAMES.base_body).id][:2].copy(), data.time
    for _ in range(10):
        e.step(model, data, a)
    d = data.xpos[model.body(NAMES.base_body).id][:2] - p0
    kv = model.actuator_gainprm[model.actuator(NAMES.base_actuators[0]).id][0]
    v_cmd = 0.5 * e.base_speed
    assert np.linalg.norm(d) / (data.time - t0) == pytest.approx(v_cmd - BASE_FRICTION / kv, rel=0.01)
    assert math.atan2(d[1], d[0]) == pytest.approx(0.6, abs=0.01)


def test_torso_position_servo_sags_by_weight_over_stiffness(env):
    """A position servo of stiffness kp holding mass M against gravity: steady error M g / kp."""
    e, model, data = env
    e.reset(model, data)
    for _ in range(20):
        e.step(model, data, _act())
    support = model.body(NAMES.prefix + "support").id
    carried = model.body_subtreemass[support]
    kp = model.actuator_gainprm[model.actuator(NAMES.torso_actuator).id][0]
    torso = data.qpos[model.jnt_qposadr[model.joint(NAMES.torso_joint).id]]
    assert TORSO0 - torso == pytest.approx(carried * 9.81 / kp, rel=0.05)


def test_arm_action_moves_the_target_by_its_scaled_delta_and_the_tool_follows(env):
    e, model, data = env
    e.reset(model, data)
    for _ in range(20):  # the torso settles under the arm's weight
        e.step(model, data, _act())
    before = e.proprioception(model, data)["target_pos_base"]
    for _ in range(4):
        e.step(model, data, _act(x=0.25))
    after = e.proprioception(model, data)["target_pos_base"]
    assert after - before == pytest.approx(
        [4 * 0.25 * POS_STEP, 0.0, 0.0], abs=2e-5
    )  # torso still settles by microns
    for _ in range(20):
        e.step(model, data, _act())
    obs = e.proprioception(model, data)
    assert np.linalg.norm(obs["ee_pos_base"] - obs["target_pos_base"]) < 0.003


def test_base_mode_carries_the_arm_and_torso_actions_lift_it(env):
    e, model, data = env
    e.reset(model, data)
    for _ in range(10):
        e.step(model, data, _act())
    ee0 = e.proprioception(model, data)["ee_pos_base"]
    for _ in range(20):
        e.step(model, data, _act(fwd=1.0, yaw=0.3, x=1.0, mode=1.0))
    for _ in range(10):
        e.step(model, data, _act(mode=1.0))
    obs = e.proprioception(model, data)
    assert np.linalg.norm(obs["base_pos"][:2]) > 0.2
    assert np.linalg.norm(obs["ee_pos_base"] - ee0) < 0.01  # the arm delta was ignored in base mode
    ctrl0 = data.ctrl[model.actuator(NAMES.torso_actuator).id]
    e.step(model, data, _act(torso=1.0))
    assert data.ctrl[model.actuator(NAMES.torso_actuator).id] - ctrl0 == pytest.approx(TORSO_STEP)
