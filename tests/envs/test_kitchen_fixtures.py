"""Kitchen fixtures: articulated parts move through their ranges under scripted loads, with the closed-form
terminal speeds of a damped joint, and the burner predicate flips exactly at 0.35 rad."""

import math

import mujoco
import numpy as np
import pytest

from rle_tasks.envs.kitchen import fixture as fx
from rle_tasks.envs.kitchen import predicates as pr
from rle_tasks.envs.kitchen.scene import build_scene


@pytest.fixture(scope="module")
def kitchen():
    scene = build_scene(1_000_003, "TurnOnStove", 3)
    model = mujoco.MjModel.from_xml_string(scene.xml)
    data = mujoco.MjData(model)
    return scene, model, data


def _reset(model, data):
    mujoco.mj_resetDataKeyframe(model, data, model.key("initial").id)
    data.ctrl[:] = 0.0
    model.opt.gravity[:] = (0.0, 0.0, -9.81)
    mujoco.mj_forward(model, data)


def _push(model, data, joint: str, load: float, seconds: float) -> tuple[float, float]:
    """Hold a generalised force on one joint (the robot and other bodies held by their servos' zero
    commands) and return (position, velocity) after ``seconds``."""
    j = model.joint(joint).id
    dof, adr = model.jnt_dofadr[j], model.jnt_qposadr[j]
    n = int(round(seconds / model.opt.timestep))
    for _ in range(n):
        data.qfrc_applied[:] = 0.0
        data.qfrc_applied[dof] = load
        mujoco.mj_step(model, data)
    data.qfrc_applied[:] = 0.0
    return float(data.qpos[adr]), float(data.qvel[dof])


def _doors(scene):
    return [
        f
        for f in scene.fixtures.values()
        if f.kind in ("fridge", "hinge_cabinet", "microwave", "wall_cabinet")
    ]


def test_every_door_swings_through_its_range_and_back(kitchen):
    scene, model, data = kitchen
    low, high = fx.DOOR_RANGE
    for f in _doors(scene):
        _reset(model, data)
        joint = f.joints[0]
        q, _ = _push(model, data, joint, 6.0, 2.0)
        assert q == pytest.approx(high, abs=0.02), f"{f.name} opened to {q:.3f} rad"
        assert pr.is_open(model, data, f)
        q, _ = _push(model, data, joint, -6.0, 2.0)
        assert q == pytest.approx(low, abs=0.01), f"{f.name} closed to {q:.3f} rad"
        assert pr.is_closed(model, data, f)


def _inertia(model, data, joint: str) -> float:
    """Joint-space inertia of one dof (armature included) [kg m^2 or kg]."""
    full = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, full)
    dof = model.jnt_dofadr[model.joint(joint).id]
    return float(full[dof, dof])


def test_door_speed_follows_the_damped_first_order_law(kitchen):
    """A hinge of inertia I, viscous damping b and Coulomb friction f under a torque tau from rest:
    omega(t) = (tau - f) / b (1 - exp(-b t / I))."""
    scene, model, data = kitchen
    f = next(d for d in _doors(scene) if d.kind == "hinge_cabinet")
    _reset(model, data)
    dof = model.jnt_dofadr[model.joint(f.joints[0]).id]
    tau, t = 1.2, 0.3
    b, fric, inertia = model.dof_damping[dof], model.dof_frictionloss[dof], _inertia(model, data, f.joints[0])
    _, omega = _push(model, data, f.joints[0], tau, t)
    assert omega == pytest.approx((tau - fric) / b * (1 - math.exp(-b * t / inertia)), rel=0.01)


def test_drawer_slides_out_to_its_travel_and_back(kitchen):
    scene, model, data = kitchen
    for f in (d for d in scene.fixtures.values() if d.kind == "drawer_cabinet"):
        _reset(model, data)
        travel = model.jnt_range[model.joint(f.joints[0]).id][1]
        assert travel == pytest.approx(fx.COUNTER_DEPTH - 0.15)
        q, _ = _push(model, data, f.joints[0], 40.0, 1.5)
        assert q == pytest.approx(travel, abs=0.005)
        assert pr.is_open(model, data, f)
        q, _ = _push(model, data, f.joints[0], -40.0, 1.5)
        assert q == pytest.approx(0.0, abs=0.005)


def test_drawer_speed_follows_the_damped_first_order_law(kitchen):
    """A slide of mass m, damping b and Coulomb friction f under a force F from rest:
    v(t) = (F - f) / b (1 - exp(-b t / m))."""
    scene, model, data = kitchen
    f = next(d for d in scene.fixtures.values() if d.kind == "drawer_cabinet")
    _reset(model, data)
    dof = model.jnt_dofadr[model.joint(f.joints[0]).id]
    force, t = 3.0, 0.3
    b, fric, mass = model.dof_damping[dof], model.dof_frictionloss[dof], _inertia(model, data, f.joints[0])
    _, v = _push(model, data, f.joints[0], force, t)
    assert v == pytest.approx((force - fric) / b * (1 - math.exp(-b * t / mass)), rel=0.01)


def test_knobs_turn_both_ways_to_their_limits(kitchen):
    scene, model, data = kitchen
    stove = scene.fixtures["stove"]
    for joint, _ in stove.burners.values():
        _reset(model, data)
        q, _ = _push(model, data, joint, 0.5, 1.5)
        assert q == pytest.approx(math.pi, abs=0.02)
        assert pr.knob_on(model, data, joint)
        q, _ = _push(model, data, joint, -0.5, 3.0)
        assert q == pytest.approx(-math.pi, abs=0.02)


@pytest.mark.parametrize(
    "angle,on",
    [(0.349, False), (0.351, True), (-0.349, False), (-0.351, True), (math.pi, True), (0.0, False)],
)
def test_burner_on_flips_at_0_35_rad_of_wrapped_angle(kitchen, angle, on):
    """on <=> wrap(q) in [0.35, 2 pi - 0.35], wrap(q) = q mod 2 pi."""
    scene, model, data = kitchen
    joint, _ = scene.fixtures["stove"].burners["front_left"]
    _reset(model, data)
    data.qpos[model.jnt_qposadr[model.joint(joint).id]] = angle
    mujoco.mj_forward(model, data)
    assert pr.knob_on(model, data, joint) is on
    assert (pr.KNOB_ON <= angle % (2 * math.pi) <= 2 * math.pi - pr.KNOB_ON) is on


def test_at_rest_no_part_touches_the_carcass(kitchen):
    """Doors, drawers and knobs are built with clearance: no contact involves them at the start."""
    scene, model, data = kitchen
    _reset(model, data)
    moving = {model.body(p).id for f in scene.fixtures.values() for p in f.parts.values()}
    for c in data.contact[: data.ncon]:
        bodies = {model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]}
        assert not bodies & moving, [model.geom(c.geom1).name, model.geom(c.geom2).name]


def test_scenes_are_deterministic_and_differ_by_seed():
    a = build_scene(17, "OpenFridge", 1)
    build_scene.cache_clear()
    b = build_scene(17, "OpenFridge", 1)
    assert a.xml == b.xml
    c = build_scene(18, "OpenFridge", 1)
    assert c.xml != a.xml
    assert np.allclose(a.episode.robot, b.episode.robot)
