"""Family 01 pick-and-place references at L3 (one pretrain episode each) and the closed forms of the
kitchen's pick-and-place predicates (``rle_tasks.envs.kitchen.predicates``)."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.envs.kitchen import predicates as pr
from rle_tasks.envs.kitchen.fixture import Interior
from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot
from rle_tasks.envs.kitchen.objects import add_object, extent
from rle_tasks.f01_robocasa_speedrun.solutions.agents import Direct, solver
from rle_tasks.f01_robocasa_speedrun.task import KITCHEN_TASKS, scenes

ACTIONS_PER_TRIAL = 1000


@pytest.mark.parametrize(
    ("task", "kitchen", "seed"),
    [("PickPlaceCounterToDrawer", 0, 0), ("PickPlaceMicrowaveToCounter", 1, 1)],
)
def test_program_solves_a_pretrain_episode(task: str, kitchen: int, seed: int) -> None:
    spec = next(k for k in KITCHEN_TASKS if k.task == task)
    session = scenes(spec, 3, Secret(PUBLIC_KEY, public=True), image_size=None).open_session(
        task_id=spec.task_id(3), budget=None
    )
    robot = Robot(Direct(session))
    robot.reset(kitchen=kitchen, seed=seed)
    assert solver(task)(robot, Motion(robot)) is True
    conditions = session.env.conditions(session.model, session.data)
    assert conditions and all(conditions.values()), conditions
    assert round(robot.obs["time"] / 0.05) < ACTIONS_PER_TRIAL


def _yaw_quat(yaw: float) -> list[float]:
    return [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]


def _set_free(model: mujoco.MjModel, data: mujoco.MjData, body: str, pos, quat) -> None:
    adr = model.jnt_qposadr[model.body(body).jntadr[0]]
    data.qpos[adr : adr + 3] = pos
    data.qpos[adr + 3 : adr + 7] = quat


@pytest.mark.parametrize(("excess", "expected"), [(0.049, True), (0.051, False)])
@pytest.mark.parametrize("axis", [0, 1, 2])
def test_inside_flips_at_the_grown_interior(excess: float, expected: bool, axis: int) -> None:
    """A box corner ``excess`` beyond the interior along ``axis`` of a turned drawer: inside iff
    excess <= INSIDE_TOL (0.05 m). With the object turned like the drawer, its corners in the drawer's
    frame are L + c +- h (L its position there, c/h its box centre/half extents), so L_axis =
    ic_axis + ih_axis + excess - c_axis - h_axis puts the farthest corner at ih_axis + excess from
    the interior's centre ic, the other axes centred (L = ic - c)."""
    yaw, base = 0.4, np.array([0.5, -0.2, 0.7])
    spec = mujoco.MjSpec()
    spec.worldbody.add_body(name="drawer", pos=base.tolist(), quat=_yaw_quat(yaw))
    add_object(spec, "obj", "butter", (0.0, 0.0, 2.0))
    model = spec.compile()
    data = mujoco.MjData(model)
    interior = Interior("drawer", (0.01, 0.02, 0.065), (0.2, 0.25, 0.065))
    c, h = (np.asarray(v) for v in extent("butter"))
    ic, ih = np.asarray(interior.center), np.asarray(interior.half)
    local = ic - c
    local[axis] = ic[axis] + ih[axis] + excess - c[axis] - h[axis]
    rot = np.array([[math.cos(yaw), -math.sin(yaw), 0.0], [math.sin(yaw), math.cos(yaw), 0.0], [0, 0, 1]])
    _set_free(model, data, "obj", base + rot @ local, _yaw_quat(yaw))
    mujoco.mj_forward(model, data)
    assert pr.inside(model, data, "obj", "butter", interior) is expected


@pytest.mark.parametrize(("d1", "d2", "expected"), [(0.251, 0.251, True), (0.251, 0.249, False)])
def test_gripper_far_at_a_quarter_metre(d1: float, d2: float, expected: bool) -> None:
    """Fingers at ``d1``/``d2`` [m] from the object's centre: far iff both exceed 0.25 m."""
    spec = mujoco.MjSpec()
    add_object(spec, "obj", "apple", (0.0, 0.0, 1.0))
    for name in ("f1", "f2"):
        spec.worldbody.add_body(name=name, mocap=True)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    p = data.xpos[model.body("obj").id].copy()
    direction = np.array([0.6, -0.0, 0.8])
    data.mocap_pos[0] = p + d1 * direction
    data.mocap_pos[1] = p - d2 * np.array([0.0, 1.0, 0.0])
    mujoco.mj_forward(model, data)
    assert pr.gripper_far(model, data, "obj", ("f1", "f2")) is expected


@pytest.mark.parametrize(
    ("offset", "lift", "expected"),
    [(-0.001, -0.001, True), (0.001, -0.001, False), (-0.001, 0.01, False)],
)
def test_in_receptacle_at_seven_tenths_of_the_radius(offset: float, lift: float, expected: bool) -> None:
    """An apple resting on a plate (lowered ``-lift`` into it) at 0.7 x the plate's radius (0.11 m)
    plus ``offset`` from its centre: in the plate iff they touch and the distance is below 0.077 m."""
    spec = mujoco.MjSpec()
    add_object(spec, "container", "plate", (0.0, 0.0, 0.0))
    add_object(spec, "obj", "apple", (0.0, 0.0, 1.0))
    model = spec.compile()
    data = mujoco.MjData(model)
    _, plate_half = extent("plate")
    radius = max(plate_half[0], plate_half[1])
    d = pr.RECEPTACLE_RADIUS * radius + offset
    top = 2 * plate_half[2]
    _set_free(model, data, "container", [0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0])
    # the apple's body origin is its lowest point (objects stand on their lowest point)
    _set_free(model, data, "obj", [d / math.sqrt(2), d / math.sqrt(2), top + lift], [1.0, 0.0, 0.0, 0.0])
    mujoco.mj_forward(model, data)
    assert pr.in_receptacle(model, data, "obj", "container", "plate") is expected
